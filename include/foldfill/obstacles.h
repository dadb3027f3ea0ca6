// Rigid obstacles the patch must stay outside of: spheres, cylinders, planes
// and triangle meshes (a body, a table). The paper's object/cloth collision
// (section 3.4; METHOD.md 2c) has spheres and cylinders, found by their
// signed distance and projected out (push_outside); planes and meshes are
// foldfill's own.
#pragma once

#include <array>
#include <memory>
#include <nlohmann/json_fwd.hpp>
#include <string>
#include <vector>

#include "foldfill/mesh.h"

namespace foldfill {

// A triangle mesh as an obstacle, with the search structures its queries
// need (built once, then only read: queries from several threads are safe).
//
// Inside and outside: a closed mesh (every edge has two faces) bounds a
// solid, its inside, whatever the orientation of its faces (they are
// oriented to bound it). An open mesh has no inside of its own: the side its
// face normals point to (faces counter-clockwise seen from the front) is
// taken as outside, the other as inside, judged at the nearest point of the
// surface (with the angle-weighted normal where that is an edge or a
// corner), so that a surface open at a few places (a scanned body) acts as
// closed away from them. A point whose nearest point is on the rim of an open
// mesh (a boundary edge or vertex) is outside: it lies beside the surface,
// not behind it, so a point behind an open sheet is inside only within the
// sheet's footprint, and one stray triangle cannot put half of space inside.
// The mesh must not intersect itself. Distances are exact up to rounding (the
// nearest point through CGAL's AABB tree); which side a point within 1e-7 of
// the mesh's bounding-box diagonal lies on is decided by exact predicates
// (CGAL's Side_of_triangle_mesh when closed, the orientation of the nearest
// face when open).
class ObstacleMesh {
 public:
  // Throws NonManifoldError("SOURCE: problem") for a mesh CGAL cannot build
  // a surface from (an edge with more than two faces, faces oriented
  // inconsistently); the mesh must have faces and finite positions, as
  // read_mesh makes sure.
  ObstacleMesh(Mesh mesh, std::string source);
  ~ObstacleMesh();
  ObstacleMesh(const ObstacleMesh&) = delete;
  ObstacleMesh& operator=(const ObstacleMesh&) = delete;

  const Mesh& mesh() const { return mesh_; }  // faces oriented outwards when closed
  const std::string& source() const { return source_; }
  bool closed() const;

  // As the functions of the same names below.
  double signed_distance(const Vec3& p) const;
  Vec3 outward_normal(const Vec3& p) const;
  bool farther_than(const Vec3& p, double gap) const;
  bool push_outside(Vec3& p) const;
  bool crosses(const std::array<Vec3, 3>& triangle) const;
  double distance(const std::array<Vec3, 3>& triangle, double limit) const;

  struct Search;  // the CGAL structures (src/embed/obstacle_mesh.cpp)

 private:
  Mesh mesh_;
  std::string source_;
  std::unique_ptr<const Search> search_;
};

struct Obstacle {
  enum class Type { Sphere, Cylinder, Plane, Mesh };
  Type type = Type::Sphere;
  Vec3 center{};         // sphere, cylinder (centre of the axis segment); plane: a point on it
  double radius = 0;     // sphere, cylinder
  double height = 0;     // cylinder: length of the axis segment
  Vec3 axis{0, 1, 0};    // cylinder: unit axis
  Vec3 normal{0, 0, 1};  // plane: unit normal, pointing to the allowed side
  std::shared_ptr<const ObstacleMesh> mesh;  // mesh: its triangles, in the same units
};

// A mesh obstacle of `mesh` (see ObstacleMesh; `source` names it in messages,
// and its errors are ObstacleMesh's).
Obstacle mesh_obstacle(Mesh mesh, const std::string& source);
// The mesh obstacle of the file `path`, read with read_mesh (and its errors).
Obstacle read_mesh_obstacle(const std::string& path);

// Parses obstacles from text: either JSON `{"obstacles": [...]}` with entries
// {"type": "sphere", "center", "radius"}, {"type": "cylinder", "center",
// "radius", "height", "euler_zxz": [psi, phi, theta]} (axis = Rz(psi) Rx(theta)
// Rz(phi) (0,1,0)) or "axis": [x,y,z], {"type": "plane", "point", "normal"},
// {"type": "mesh", "file": "body.obj"} (a path relative to the folder of
// `source`, read by read_mesh_obstacle); or the prototype's text lines
// `sphere x y z r` / `cylinder x y z r h a1 a2 a3`. Throws UsageError
// naming `source` for malformed input, and the errors of read_mesh for a
// mesh file that cannot be read.
std::vector<Obstacle> parse_obstacles(const std::string& text, const std::string& source);
// The same for a JSON document already parsed: `{"obstacles": [...]}` or the
// list alone (a mesh entry's file is relative to the folder of `source`).
std::vector<Obstacle> obstacles_from_json(const nlohmann::json& document,
                                          const std::string& source);

// parse_obstacles of the file `path` (naming it); CannotReadError when it
// cannot be read.
std::vector<Obstacle> read_obstacles(const std::string& path);

// Signed distance from `p` to the obstacle's surface (negative inside).
double signed_distance(const Obstacle& obstacle, const Vec3& p);

// The outward unit normal of the obstacle's surface seen from `p`: the
// gradient of signed_distance. (0, 0, 0) where that has no direction: a
// sphere's centre, and inside a cylinder on its axis (where the side is
// nearest) or on its mid-plane (where the caps are).
Vec3 outward_normal(const Obstacle& obstacle, const Vec3& p);

// Whether `p` is certainly farther than `gap` (>= 0) from the obstacle's
// surface, by a test cheaper than signed_distance (no square root): true
// only where signed_distance(obstacle, p) > gap, and false when in doubt
// (near a cylinder's rims, within a hair of the distance `gap`).
bool farther_than(const Obstacle& obstacle, const Vec3& p, double gap);

// Moves `p` to the nearest point of the surface when it is inside; returns
// whether it moved. A mesh obstacle also moves a point on its surface, and
// puts it just outside, 1e-9 of its bounding-box diagonal off the surface
// (more where that is not yet outside by the exact test): so that a patch
// resting on it does not touch its triangles.
bool push_outside(const Obstacle& obstacle, Vec3& p);

// The obstacle in normalised coordinates (p - origin) / scale (a mesh
// obstacle's mesh moved and scaled, and its search structures built anew).
// Throws InternalError unless `scale` is positive.
Obstacle normalized(const Obstacle& obstacle, const Vec3& origin, double scale);

// Whether the triangle crosses into the obstacle. Sphere, cylinder, plane: it
// reaches inside deeper than `tolerance` (>= 0), the rounding of a point left
// on the surface by push_outside (its smallest signed distance is below
// -tolerance; the cylinder's, a convex function, is minimised over the
// triangle by nested golden-section searches). Mesh: the triangle intersects
// one of the mesh's (CGAL's exact test), or has a corner inside a closed one;
// `tolerance` is not used.
bool crosses(const Obstacle& obstacle, const std::array<Vec3, 3>& triangle, double tolerance);

// The distance from the triangle to the obstacle, 0 where it crosses into it
// (see crosses, with no tolerance), and `limit` where it is farther than
// `limit` (which saves work).
double distance(const Obstacle& obstacle, const std::array<Vec3, 3>& triangle, double limit);

// The most faces tessellate_obstacle returns.
constexpr int kMaxObstacleFaces = 100000;

// What a mesh from tessellate_obstacle was made for, and how close it is.
struct TessellationBounds {
  // The edge length the faces were made for: the one asked for, or a larger
  // one where that would have made more than kMaxObstacleFaces faces.
  double edge_length = 0;
  // Every point of the mesh has a signed distance to the obstacle in
  // [-inset, gap - inset], up to rounding; gap <= 0.25 * edge_length.
  double gap = 0;
};

// The part of a sphere, cylinder or plane obstacle near `box` as a triangle
// mesh (positions and faces only), so that contacts can be handled against
// triangles alone. The mesh is (a piece of) the boundary of a convex
// polyhedron that contains the obstacle shrunk by `inset` (>= 0), and lies
// between the shrunk surface and `gap` beyond it: a point outside that
// polyhedron is no deeper in the obstacle than `inset`. Faces are oriented
// outwards (counter-clockwise seen from the allowed side).
//
// Sphere of radius R: with rho = R - inset, a cube-sphere (each face of a
// cube a grid of equal angles, each cell split into two triangles) whose
// vertices are all at rho / cos(alpha) from the centre, alpha the largest
// angular radius of a face's circumcircle. Every face's plane is then at
// least rho from the centre, so the ball of radius rho is inside, and gap =
// rho (1 / cos(alpha) - 1). The grid's steps are about `edge_length` on the
// ball (its diagonals up to 1.45 times that), finer where that is needed for
// gap <= 0.25 * edge_length.
// Cylinder of radius R and height H: a prism of n sides around the cylinder
// of radius rho = R - inset and height H - 2 inset, its vertices at rho /
// cos(pi / n), so gap = rho (1 / cos(pi / n) - 1); n makes the sides about
// `edge_length` wide, or is more where that is needed for gap <= 0.25 *
// edge_length. Rows are about `edge_length` apart along the axis. Each cap
// is rings about `edge_length` apart, with about as many vertices each as
// makes its edges `edge_length`, the outermost ring the prism's rim (the
// edges across rings are up to 1.7 times `edge_length`).
// Plane: one rectangle (two triangles) on the plane moved by `inset` against
// its normal, covering the projection of `box` grown by `edge_length`; gap =
// 0. Being flat, it is exact at any size: the only faces much larger than
// `edge_length`.
//
// Only faces near `box` are kept: those whose bounding box overlaps `box`
// grown by `edge_length`, among those that the box's directions from the
// centre (the axis) can see. The part near the box is complete: the ray
// through a point of the shrunk surface inside `box`, from the sphere's
// centre, from the cylinder's axis (along the axis for a cap) or along the
// plane's normal, meets a face within `gap` of that point. The mesh is
// closed where `box` holds the whole obstacle. A sphere or cylinder that
// nothing is left of once shrunk (inset >= R, or 2 inset >= H) gives no
// faces, and so does a plane whose moved plane misses the grown box.
//
// At most kMaxObstacleFaces faces: where the box would need more, the faces
// are made larger (bounds->edge_length) until they fit; they are never finer
// than 2^-24 of the radius (or half-height). Scale-free (the obstacle, the
// box, `edge_length` and `inset` scaled together scale the mesh) and
// deterministic. All of the above holds up to rounding. `bounds`, when
// given, receives the edge length and the gap.
// Throws UsageError for a mesh obstacle, an `edge_length` that is not
// positive and finite, an `inset` that is negative or not finite, or a box
// with non-finite corners or low above high.
Mesh tessellate_obstacle(const Obstacle& obstacle, const Box3& box, double edge_length,
                         double inset, TessellationBounds* bounds = nullptr);

}  // namespace foldfill
