// Closed and open surfaces with holes cut out, generated in code: the ground
// truth for telling holes from outer edges and tube ends (hole selection) on
// shapes the reference data lacks (closed surfaces, sleeves, domes, holes of
// 3 to 5 vertices, holes longer than the cloth's edge).
//
// Every surface is a manifold triangle mesh, consistently oriented (faces
// counter-clockwise seen from outside on closed surfaces), without
// unreferenced vertices. Each hole is cut by removing faces (whose centroid
// lies within a geodesic distance of a centre, or an exact small set of
// faces), then cleaned so that its boundary is one simple loop: faces with two
// removed neighbours of the same hole are removed too, and so are the smaller
// fans at a vertex the hole would touch twice. The generators are
// deterministic: the same options give the same mesh, bit for bit, and throw
// nothing.
#pragma once

#include <cstdint>
#include <vector>

#include "foldfill/mesh.h"

namespace foldfill {

// A surface and, for each of its boundary loops, one vertex on it: the holes
// cut out (to be filled) and the loops that are not holes (a sheet's outer
// edge, a tube's ends: to be left open).
struct HoledSurface {
  Mesh mesh;
  std::vector<int> hole_vertices;  // one vertex on each hole, in the order of the options
  std::vector<int> open_vertices;  // one vertex on each loop that is not a hole
};

// A sphere (subdivided icosahedron, projected) with a large cap removed around
// +z, `cap_degrees` half-angle (its loop turns by 360 - 2 (1 - cos) 180
// degrees: 152 at 65 degrees), and `small_holes` small ones of geodesic radius
// `small_radius` (in radii) spread around a circle at 130 degrees from +z.
// hole_vertices: the cap first.
struct SphereSurfaceOptions {
  double radius = 1;
  int subdivisions = 4;  // 10 * 4^n + 2 vertices before the cut
  double cap_degrees = 65;
  int small_holes = 3;
  double small_radius = 0.25;
};
HoledSurface make_holed_sphere(const SphereSurfaceOptions& options = {});

// A torus around z (major radius `major`, tube radius `minor`), a grid of
// about `edge_length`, with three holes of geodesic radius `hole_radius`: on
// the outer side (positive curvature), the inner side (negative curvature) and
// the top, in that order.
struct TorusSurfaceOptions {
  double major = 2, minor = 0.75;
  double edge_length = 0.08;
  double hole_radius = 0.35;
};
HoledSurface make_holed_torus(const TorusSurfaceOptions& options = {});

// A closed blob like a statue: a sphere of `radius` displaced radially by
// `bumps` smooth bumps and low-frequency waves, with `holes` well separated
// holes whose loops have 3 to 60 vertices. Hole i has 3 vertices when
// i % 10 == 0 (one face removed), 4 when i % 10 == 1 (two faces), 5 when
// i % 10 == 2 (three faces in a fan), otherwise it is a geodesic disk; the
// bumps are centred on holes 0, `holes / bumps`, 2 `holes / bumps`, ...
// (holes on bump tips). `seed` turns the layout.
struct BlobSurfaceOptions {
  double radius = 1;
  int subdivisions = 6;
  int holes = 60;
  int bumps = 6;
  std::uint64_t seed = 1;
};
HoledSurface make_holed_blob(const BlobSurfaceOptions& options = {});

// An open cylinder of `radius` around z over [0, length] (two open ends, the
// loops of open_vertices), with an elliptic hole in its side whose loop is
// longer than either end's: half-axes `hole_half_length` along z and
// `hole_half_width` around (arc length), centred halfway.
struct SleeveSurfaceOptions {
  double radius = 1, length = 5;
  double edge_length = 0.1;
  double hole_half_length = 1.6, hole_half_width = 1.1;
};
HoledSurface make_holed_sleeve(const SleeveSurfaceOptions& options = {});

// A square sheet of flat side `size`, gently folded (one sinusoidal fold of
// `amplitude`, exactly developable), with a flower-shaped hole in its middle
// whose loop is longer than the sheet's outer edge: flat radius
// size * (0.3 + 0.11 cos(9 angle)).
struct SheetSurfaceOptions {
  double size = 3;
  double edge_length = 0.04;
  double amplitude = 0.1;
};
HoledSurface make_sheet_with_long_hole(const SheetSurfaceOptions& options = {});

// A spherical cap sheet (half-angle `rim_degrees` about +z, the open rim) with
// a hole of geodesic radius `hole_radius` (in radii) centred `hole_degrees`
// from the top: its surroundings are not developable.
struct DomeSurfaceOptions {
  double radius = 1;
  int subdivisions = 5;
  double rim_degrees = 70;
  double hole_degrees = 20;
  double hole_radius = 0.3;
};
HoledSurface make_holed_dome(const DomeSurfaceOptions& options = {});

// A closed cube [0, size]^3, `cells` x `cells` squares per side, with the
// corner (size, size, size) cut out: all its faces removed, which leaves a
// 4-vertex loop (the diagonals are laid so that one side has two triangles at
// that corner and the other two sides one each).
struct BoxSurfaceOptions {
  double size = 1;
  int cells = 4;
};
HoledSurface make_box_with_corner_hole(const BoxSurfaceOptions& options = {});

// A gently folded square sheet (flat side `size`) with three small holes of
// exactly 3, 4 and 5 loop vertices (one, two and three faces around a vertex
// removed), in that order.
struct SmallHolesSurfaceOptions {
  double size = 2;
  double edge_length = 0.1;
  double amplitude = 0.1;
};
HoledSurface make_sheet_with_small_holes(const SmallHolesSurfaceOptions& options = {});

// A ruffled disk: a cone over the closed curve normalize(cos t, sin t,
// ruffle sin(3 t)), whose apex angle (about 2.68 pi at ruffle 0.5) exceeds a
// full turn; flat everywhere but at the apex. It has a C-shaped slot of width
// `slot_width` at geodesic distance `slot_radius` from the apex, running
// around all of it but an intrinsic angle `slot_gap`: the slot's outline turns
// by 360 degrees yet goes around by more than 360 in the flat, so the LSCM
// flattening of its strip overlaps itself. The sheet's outer edge is at
// geodesic distance `outer_radius`.
struct RuffleSurfaceOptions {
  double ruffle = 0.5;
  double outer_radius = 1.5;
  double edge_length = 0.02;
  double slot_radius = 1.0, slot_width = 0.1, slot_gap = 0.8;
};
HoledSurface make_ruffle_with_c_slot(const RuffleSurfaceOptions& options = {});

}  // namespace foldfill
