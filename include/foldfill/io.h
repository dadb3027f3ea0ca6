// Reading and writing triangle meshes: OBJ, PLY (ASCII / binary), OFF, STL.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "foldfill/mesh.h"

namespace foldfill {

enum class MeshFormat { Obj, Ply, Off, Stl };

// The format named by a path's extension (case-insensitive); throws
// UsageError for an unknown extension.
MeshFormat format_from_path(const std::string& path);

// Parses a whole file held in memory. `source` names it in error messages.
// Polygons are split into triangle fans; STL corners with equal positions
// (+0 and -0 alike) are welded. Text may start with a UTF-8 byte order mark;
// counts in headers must match the data. Validates the result (finite
// coordinates, face indices in range, three distinct vertices per face).
// Throws BadFormatError for content that is not a mesh of `format` (empty,
// garbage, truncated, counts that do not match), NonFiniteCoordinateError and
// BadFaceError as validate_mesh, all "SOURCE: problem" (with the line where
// there is one); messages count vertices and faces from 0.
//
// Besides the geometry it keeps what a writer can give back (see Mesh): OBJ
// texture coordinates, normals and the `mtllib`, `o`, `g`, `usemtl`, `s`
// statements; PLY scalar properties of vertices and faces and the type of
// the coordinates. What is dropped or mended on the way is said in
// `warnings`, one line "SOURCE: what" each (when given): OBJ references to
// texture coordinates or normals the file does not have (dropped, -1), PLY
// list properties other than the face indices, PLY elements other than
// vertex and face. An integer PLY property `foldfill_hole` (the marks of an
// earlier fill) is read into Mesh::vertex_hole / face_hole, a fill replacing
// them with its own; one that is not an integer, or a second one, is dropped
// with a warning.
Mesh parse_mesh(std::string_view bytes, MeshFormat format, const std::string& source,
                std::vector<std::string>* warnings = nullptr);

// Reads `path` (format from its extension). Throws UsageError for an unknown
// extension, CannotReadError if it cannot be opened or read (or is a
// folder), otherwise as parse_mesh.
Mesh read_mesh(const std::string& path, std::vector<std::string>* warnings = nullptr);

// Checks a mesh built in memory as parse_mesh checks what it read: finite
// coordinates, face indices in range, three distinct vertices per face, the
// per-element data of one entry per element. Throws
// NonFiniteCoordinateError or BadFaceError naming `source` and the vertex
// or face (counted from 0).
void validate_mesh(const Mesh& mesh, const std::string& source = "mesh");

struct WriteOptions {
  bool binary = true;  // PLY and STL: binary (PLY little endian) or ASCII
};

// Writes `mesh` to `path` in the format of its extension. Positions are written
// with round-trip precision (PLY in mesh.coordinate_type; STL is a float32
// format). What the format can hold of the rest is written too:
//  - OBJ: texture coordinates and normals of the faces that have them on all
//    corners, the statements of obj_statements before the faces they came
//    before, and each run of new faces under `g foldfill_hole_<loop id>`;
//  - PLY: the vertex and face properties in their own types, then, when the
//    mesh has marks, an `int foldfill_hole` property on vertices and faces;
//  - OFF and STL: positions and faces only.
// The file is written to a temporary name beside `path` and renamed into
// place, so a failure leaves no partial file. Precondition: `mesh` is valid
// (validate_mesh). Throws UsageError for an unknown extension,
// CannotWriteError when the file cannot be written.
void write_mesh(const Mesh& mesh, const std::string& path, const WriteOptions& options = {});

// Same as write_mesh but to a string (used by tests and fuzzers). Throws
// nothing for a valid mesh (validate_mesh).
std::string serialize_mesh(const Mesh& mesh, MeshFormat format, const WriteOptions& options = {});

}  // namespace foldfill
