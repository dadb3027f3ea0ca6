// What a fill appended, and where: the marks of the new elements, the values
// the carried per-element data takes on them, and each hole's index ranges
// and area.
#pragma once

#include <vector>

#include "foldfill/holes.h"
#include "foldfill/inpaint.h"
#include "foldfill/mesh.h"

namespace foldfill {

// Called by the fills on their output `mesh`, whose patches were appended
// after the input's vertices and faces in the order of `report.holes` (a
// filled hole's patch_vertex_count vertices, then the next hole's; the same
// for faces). Sets:
//  - report.holes[k].new_vertices / new_faces, the ranges of each filled
//    hole's new elements, and patch_area, the area of its new faces;
//  - mesh.vertex_hole / face_hole: -1 for the input's elements, the loop id
//    for new ones;
//  - the values of the carried PLY properties on new elements: on a new
//    vertex, colours (`red`, `green`, `blue`, `alpha`) and normals (`nx`,
//    `ny`, `nz`, renormalised when all three are there) are the mean over the
//    vertices of its hole's loop (in `loops`, by loop id), rounded to the
//    property's type; every other property is 0, on new vertices and faces.
// Throws InternalError when the counts of the report do not add up to the
// elements appended.
void mark_new_elements(Mesh& mesh, const std::vector<BoundaryLoop>& loops, FillReport& report);

}  // namespace foldfill
