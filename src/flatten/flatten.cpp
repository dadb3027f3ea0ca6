// The strip around a hole and its LSCM flattening (see flatten.h). The strip
// is checked to be a connected planar surface (an annulus, or a ring with
// islands where the loop comes back near itself) with the loop as one of its
// boundaries, the shapes on which the flattened loop is a meaningful outline
// of the hole. LSCM is solved on the normal equations of the real least-squares
// form with a sparse Cholesky (LDLT) factorisation: strips have a few
// thousand vertices and, on developable input, an exact zero-energy solution,
// so the squared condition number costs no useful accuracy.
#include "foldfill/flatten.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_2_algorithms.h>

#include <Eigen/Sparse>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <string>
#include <utility>
#include <vector>

#include "foldfill/error.h"
#include "foldfill/topology.h"
#include "foldfill/vec3.h"

namespace foldfill {
namespace {

// A flattened triangle counts as degenerate (with the flipped ones) when its
// smallest height is below this fraction of its longest edge: its rest shape
// would be useless to every energy downstream.
constexpr double kDegenerateHeight = 1e-8;
// 3D triangles thinner than this (same measure) carry no conformal
// information; they are left out of the LSCM energy.
constexpr double kZeroAreaHeight = 1e-12;
// Steps of the repaired outline from the loop's own angles to a circle's.
constexpr int kRepairSteps = 8;

// ---- Strip extraction and its topology check -------------------------------

// The refusal of a loop: "SOURCE: loop ID: reason".
struct LoopRefusal {
  const std::string& source;
  int loop_id;
  NotADiskError operator()(const std::string& reason) const {
    return NotADiskError(source + ": loop " + std::to_string(loop_id) + ": " + reason);
  }
};

// Corners of the strip's faces joined across shared edges: the corners of
// one vertex that end up in one set form one fan of faces around it.
class CornerSets {
 public:
  explicit CornerSets(int corner_count) : parent_(corner_count) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  int find(int c) {
    while (parent_[c] != c) c = parent_[c] = parent_[parent_[c]];
    return c;
  }
  void join(int a, int b) { parent_[find(a)] = find(b); }

 private:
  std::vector<int> parent_;
};

int corner_of(const std::vector<Tri>& faces, int face, int vertex) {
  const Tri& f = faces[face];
  return 3 * face + (f[0] == vertex ? 0 : f[1] == vertex ? 1 : 2);
}

// The corners of `faces` grouped into fans: joined across interior edges.
CornerSets fans_of_corners(const std::vector<Tri>& faces, const EdgeTopology& topology) {
  CornerSets corners(3 * static_cast<int>(faces.size()));
  for (const Edge& e : topology.edges) {
    if (e.is_boundary()) continue;
    for (int v : {e.v0, e.v1})
      corners.join(corner_of(faces, e.face[0], v), corner_of(faces, e.face[1], v));
  }
  return corners;
}

// Number of fans (groups of faces joined by edges) around each vertex.
std::vector<int> fan_counts(const std::vector<Tri>& faces, int vertex_count,
                            const EdgeTopology& topology) {
  CornerSets corners = fans_of_corners(faces, topology);
  std::vector<int> fans(vertex_count, 0);
  for (int f = 0; f < static_cast<int>(faces.size()); ++f)
    for (int k = 0; k < 3; ++k)
      if (corners.find(3 * f + k) == 3 * f + k) ++fans[faces[f][k]];
  return fans;
}

// `faces` with every fan but the first of each vertex below `loop_size` on a
// new vertex of its own (numbered from `vertex_count` on, which is updated).
std::vector<Tri> unpinch(const std::vector<Tri>& faces, int loop_size, const EdgeTopology& topology,
                         int& vertex_count) {
  CornerSets corners = fans_of_corners(faces, topology);
  std::vector<Tri> result = faces;
  std::vector<int> first_fan(loop_size, -1), copy_of_fan(3 * faces.size(), -1);
  for (int f = 0; f < static_cast<int>(faces.size()); ++f) {
    for (int k = 0; k < 3; ++k) {
      const int v = faces[f][k];
      if (v >= loop_size) continue;
      const int fan = corners.find(3 * f + k);
      if (first_fan[v] < 0) first_fan[v] = fan;
      if (fan == first_fan[v]) continue;
      if (copy_of_fan[fan] < 0) copy_of_fan[fan] = vertex_count++;
      result[f][k] = copy_of_fan[fan];
    }
  }
  return result;
}

// Number of closed chains of boundary edges, given that every vertex has one
// fan (so a boundary vertex has exactly one boundary edge out and one in).
int boundary_loop_count(int vertex_count, const EdgeTopology& topology) {
  std::vector<int> next(vertex_count, -1);
  for (const Edge& e : topology.edges) {
    if (!e.is_boundary()) continue;
    // Follow the faces' own direction; any consistent direction will do.
    if (e.face[0] >= 0)
      next[e.v0] = e.v1;
    else
      next[e.v1] = e.v0;
  }
  int loops = 0;
  std::vector<bool> seen(vertex_count, false);
  for (int start = 0; start < vertex_count; ++start) {
    if (next[start] < 0 || seen[start]) continue;
    ++loops;
    for (int v = start; v >= 0 && !seen[v]; v = next[v]) seen[v] = true;
  }
  return loops;
}

const Edge* find_edge(const EdgeTopology& topology, int a, int b) {
  const int v0 = std::min(a, b), v1 = std::max(a, b);
  const auto it =
      std::lower_bound(topology.edges.begin(), topology.edges.end(), std::make_pair(v0, v1),
                       [](const Edge& e, const std::pair<int, int>& key) {
                         return std::make_pair(e.v0, e.v1) < key;
                       });
  return it != topology.edges.end() && it->v0 == v0 && it->v1 == v1 ? &*it : nullptr;
}

// Throws `not_a_disk(reason)` unless the strip is a connected planar surface
// whose inner boundary is the loop.
void check_flat_ring(const Strip& strip, const std::string& source, const LoopRefusal& not_a_disk) {
  const int vertex_count = static_cast<int>(strip.positions.size());
  EdgeTopology topology;
  try {
    topology = build_edge_topology(strip.faces, vertex_count, source);
  } catch (const Error& error) {
    // Its message names strip-local indices; the mesh's are what the user has.
    const NotADiskError refusal =
        not_a_disk("the faces around it are not a consistently oriented manifold");
    throw_error(error.kind(), refusal.what());
  }

  for (int k = 0; k < strip.loop_size; ++k) {
    const Edge* e = find_edge(topology, k, (k + 1) % strip.loop_size);
    if (!e || !e->is_boundary())
      throw not_a_disk("its edge (" + std::to_string(strip.to_input[k]) + ", " +
                       std::to_string(strip.to_input[(k + 1) % strip.loop_size]) +
                       ") is not a boundary edge of the mesh");
  }

  const std::vector<int> fans = fan_counts(strip.faces, vertex_count, topology);
  for (int v = strip.loop_size; v < vertex_count; ++v) {
    if (fans[v] > 1)
      throw not_a_disk("the faces around it pinch at vertex " + std::to_string(strip.to_input[v]) +
                       " (the hole comes back within one edge of itself there)");
  }
  // A loop vertex with several fans is one where the mesh's boundary was split
  // (a hole touching the outer edge or another hole there): the ring is then
  // checked with each extra fan on a copy of the vertex, which opens it into a
  // disk (or a disk with islands). LSCM itself works on the pinched strip.
  const bool pinched = std::any_of(fans.begin(), fans.begin() + strip.loop_size,
                                   [](int count) { return count > 1; });
  int ring_vertex_count = vertex_count;
  std::vector<Tri> ring_faces;
  if (pinched) {
    ring_faces = unpinch(strip.faces, strip.loop_size, topology, ring_vertex_count);
    topology = build_edge_topology(ring_faces, ring_vertex_count, source);
  }
  const int face_count = static_cast<int>(strip.faces.size());
  const int euler = ring_vertex_count - static_cast<int>(topology.edges.size()) + face_count;
  const int boundaries = boundary_loop_count(ring_vertex_count, topology);
  // A connected surface with b boundaries is planar (it lies flat) when its
  // Euler characteristic is 2 - b. An annulus (b = 2) is the usual strip; a
  // loop that comes back within an edge of itself gives a strip that bridges
  // the gap, a ring with islands (b > 2), which flattens as well.
  if (boundaries < (pinched ? 1 : 2) || euler != 2 - boundaries)
    throw not_a_disk("the faces around it do not form a flat ring around the hole (" +
                     std::to_string(boundaries) + " boundary loops, Euler characteristic " +
                     std::to_string(euler) + "), so the hole is not a disk surrounded by surface");
}

// ---- LSCM -------------------------------------------------------------------

using SparseMatrix = Eigen::SparseMatrix<double>;
using Triplet = Eigen::Triplet<double>;

// Coordinates of a 3D triangle in its own plane, counter-clockwise: corner 0
// at the origin, corner 1 on the x axis.
std::array<Vec2, 3> local_frame(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  const Vec3 e1 = sub(p1, p0), e2 = sub(p2, p0);
  const double l1 = norm(e1);
  const double x2 = dot(e1, e2) / l1;
  const double y2 = norm(cross(e1, e2)) / l1;
  return {Vec2{0, 0}, Vec2{l1, 0}, Vec2{x2, y2}};
}

// LSCM (Lévy et al. 2002) in real form. In a triangle of area A with local
// corners q_j and edges e_j = q_{j+2} - q_{j+1}, a linear map (u, v) is
// conformal when rot90(grad u) = grad v; the residual
//   rot90(grad u) - grad v = -sum_j (u_j e_j + v_j rot90(e_j)) / (2A)
// gives two rows per triangle, weighted by sqrt(A). Unknowns are interleaved
// (u_i at 2i, v_i at 2i + 1); the first strip vertices are pinned at `pins`
// (the loop's first vertices come first).
std::vector<Vec2> solve_lscm(const Strip& strip, const std::vector<Vec2>& pins,
                             const std::string& source) {
  const int vertex_count = static_cast<int>(strip.positions.size());
  const int pin_variables = 2 * static_cast<int>(pins.size());
  std::vector<double> pinned(pin_variables);
  for (size_t k = 0; k < pins.size(); ++k) {
    pinned[2 * k] = pins[k][0];
    pinned[2 * k + 1] = pins[k][1];
  }

  // Free unknown of each variable, -1 for the pinned ones.
  const int free_count = 2 * vertex_count - pin_variables;
  const auto free_index = [&](int variable) {
    return variable < pin_variables ? -1 : variable - pin_variables;
  };

  std::vector<Triplet> entries;
  entries.reserve(strip.faces.size() * 12);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(2 * static_cast<Eigen::Index>(strip.faces.size()));
  int row = 0;
  for (const Tri& f : strip.faces) {
    const auto q = local_frame(strip.positions[f[0]], strip.positions[f[1]], strip.positions[f[2]]);
    const double twice_area = q[1][0] * q[2][1];
    const double longest = std::max({q[1][0], norm(q[2]), norm(sub(q[2], q[1]))});
    if (!(twice_area > kZeroAreaHeight * longest * longest)) continue;
    const double weight = 1 / std::sqrt(2 * twice_area);  // sqrt(A) / (2A)
    for (int j = 0; j < 3; ++j) {
      const Vec2 e = sub(q[(j + 2) % 3], q[(j + 1) % 3]);
      // Row x: -u_j e_x + v_j e_y; row y: -u_j e_y - v_j e_x.
      const double coefficients[2][2] = {{-e[0], e[1]}, {-e[1], -e[0]}};
      for (int r = 0; r < 2; ++r)
        for (int c = 0; c < 2; ++c) {
          const int variable = 2 * f[j] + c;
          const double value = weight * coefficients[r][c];
          if (free_index(variable) >= 0)
            entries.emplace_back(row + r, free_index(variable), value);
          else
            rhs[row + r] -= value * pinned[variable];
        }
    }
    row += 2;
  }
  SparseMatrix system(row, free_count);
  system.setFromTriplets(entries.begin(), entries.end());
  const SparseMatrix normal = SparseMatrix(system.transpose() * system);
  Eigen::SimplicialLDLT<SparseMatrix> solver;
  Eigen::VectorXd solution = Eigen::VectorXd::Zero(free_count);
  if (free_count > 0) {
    solver.compute(normal);
    if (solver.info() == Eigen::Success)
      solution = solver.solve(system.transpose() * rhs.head(row));
  }
  if ((free_count > 0 && solver.info() != Eigen::Success) || !solution.allFinite())
    throw FillFailedError(source + ": the flattening (LSCM) system of the strip " +
                          "is singular; its triangles may be degenerate");

  std::vector<Vec2> uv(vertex_count);
  for (size_t k = 0; k < pins.size(); ++k) uv[k] = pins[k];
  for (int v = static_cast<int>(pins.size()); v < vertex_count; ++v)
    uv[v] = {solution[free_index(2 * v)], solution[free_index(2 * v + 1)]};
  return uv;
}

double twice_signed_area(const std::vector<Vec2>& uv, const Tri& f) {
  return cross(sub(uv[f[1]], uv[f[0]]), sub(uv[f[2]], uv[f[0]]));
}

// Mirrors v when the strip came out clockwise as a whole.
void make_counter_clockwise(const Strip& strip, std::vector<Vec2>& uv) {
  double total = 0;
  for (const Tri& f : strip.faces) total += twice_signed_area(uv, f);
  if (total < 0)
    for (Vec2& p : uv) p[1] = -p[1];
}

int count_flipped(const Strip& strip, const std::vector<Vec2>& uv) {
  int flipped = 0;
  for (const Tri& f : strip.faces) {
    const double longest = std::max({norm(sub(uv[f[1]], uv[f[0]])), norm(sub(uv[f[2]], uv[f[1]])),
                                     norm(sub(uv[f[0]], uv[f[2]]))});
    flipped += !(twice_signed_area(uv, f) > kDegenerateHeight * longest * longest);
  }
  return flipped;
}

// Loop edge lengths and the strip's angle sums at the loop vertices, 2D
// against 3D.
void measure_fit(const Strip& strip, Flattening& flat) {
  const int n = strip.loop_size;
  double length_sum2 = 0;
  for (int k = 0; k < n; ++k) {
    const int a = k, b = (k + 1) % n;
    const double length3 = norm(sub(strip.positions[b], strip.positions[a]));
    const double error = std::abs(norm(sub(flat.uv[b], flat.uv[a])) - length3) / length3;
    length_sum2 += error * error;
    flat.edge_length_max_rel = std::max(flat.edge_length_max_rel, error);
  }
  flat.edge_length_rms_rel = std::sqrt(length_sum2 / n);

  std::vector<double> angle3(n, 0), angle2(n, 0);
  for (const Tri& f : strip.faces)
    for (int k = 0; k < 3; ++k) {
      const int v = f[k], b = f[(k + 1) % 3], c = f[(k + 2) % 3];
      if (v >= n) continue;
      angle3[v] += corner_angle(strip.positions[v], strip.positions[b], strip.positions[c]);
      angle2[v] += corner_angle(flat.uv[v], flat.uv[b], flat.uv[c]);
    }
  double angle_sum2 = 0;
  for (int v = 0; v < n; ++v) {
    const double error = std::abs(angle2[v] - angle3[v]);
    angle_sum2 += error * error;
    flat.angle_sum_max = std::max(flat.angle_sum_max, error);
  }
  flat.angle_sum_rms = std::sqrt(angle_sum2 / n);
}

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;

std::vector<Kernel::Point_2> to_points(const std::vector<Vec2>& polygon) {
  std::vector<Kernel::Point_2> points;
  points.reserve(polygon.size());
  for (const Vec2& p : polygon) points.emplace_back(p[0], p[1]);
  return points;
}

// Whether the polygon is simple, decided with exact predicates (a sweep).
bool is_simple(const std::vector<Vec2>& polygon) {
  const std::vector<Kernel::Point_2> points = to_points(polygon);
  return CGAL::is_simple_2(points.begin(), points.end(), Kernel());
}

// Whether the simple polygon runs counter-clockwise (exact predicate).
bool is_counter_clockwise(const std::vector<Vec2>& polygon) {
  const std::vector<Kernel::Point_2> points = to_points(polygon);
  return CGAL::orientation_2(points.begin(), points.end(), Kernel()) == CGAL::COUNTERCLOCKWISE;
}

// Throws unless `loop` is flagged a disk and has at least 3 distinct vertices
// of `mesh`.
void check_loop(const Mesh& mesh, const BoundaryLoop& loop, const LoopRefusal& not_a_disk) {
  if (!loop.is_disk)
    throw not_a_disk(loop.reason.empty() ? "it is not the boundary of a disk" : loop.reason);
  if (loop.vertices.size() < 3)
    throw not_a_disk("it has " + std::to_string(loop.vertices.size()) +
                     " vertices, at least 3 are needed");
  for (int v : loop.vertices)
    if (v < 0 || v >= mesh.vertex_count())
      throw not_a_disk("vertex index " + std::to_string(v) + " is out of range");
  std::vector<int> sorted = loop.vertices;
  std::sort(sorted.begin(), sorted.end());
  const auto repeated = std::adjacent_find(sorted.begin(), sorted.end());
  if (repeated != sorted.end())
    throw not_a_disk("it passes vertex " + std::to_string(*repeated) + " twice");
}

// The strip made of the input faces `faces` (ascending): loop vertices first,
// in loop order, then the others in order of first appearance in those faces.
// Input vertices are looked up in the sorted list of the strip's vertices, so
// the cost follows the strip's size, not the mesh's.
Strip make_strip(const Mesh& mesh, const BoundaryLoop& loop, const std::vector<int>& faces,
                 const std::string& source, const LoopRefusal& not_a_disk) {
  std::vector<int> vertices;
  vertices.reserve(3 * faces.size());
  for (int f : faces) vertices.insert(vertices.end(), mesh.faces[f].begin(), mesh.faces[f].end());
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  std::vector<int> local(vertices.size(), -1);  // by position in `vertices`
  const auto slot = [&](int v) -> int& {
    return local[std::lower_bound(vertices.begin(), vertices.end(), v) - vertices.begin()];
  };

  Strip strip;
  strip.loop_size = static_cast<int>(loop.vertices.size());
  strip.to_input = loop.vertices;
  for (int k = 0; k < strip.loop_size; ++k) {
    if (!std::binary_search(vertices.begin(), vertices.end(), loop.vertices[k]))
      throw not_a_disk("vertex " + std::to_string(loop.vertices[k]) + " has no face");
    slot(loop.vertices[k]) = k;
  }
  strip.faces.reserve(faces.size());
  for (int f : faces) {
    Tri strip_face{};
    for (int k = 0; k < 3; ++k) {
      int& v = slot(mesh.faces[f][k]);
      if (v < 0) {
        v = static_cast<int>(strip.to_input.size());
        strip.to_input.push_back(mesh.faces[f][k]);
      }
      strip_face[k] = v;
    }
    strip.faces.push_back(strip_face);
  }
  strip.input_faces = faces;
  strip.positions.reserve(strip.to_input.size());
  for (int v : strip.to_input) strip.positions.push_back(mesh.positions[v]);

  check_flat_ring(strip, source, not_a_disk);
  return strip;
}

}  // namespace

Strip extract_strip(const Mesh& mesh, const BoundaryLoop& loop, const std::string& source) {
  const LoopRefusal not_a_disk{source, loop.id};
  check_loop(mesh, loop, not_a_disk);
  std::vector<char> on_loop(mesh.vertex_count(), 0);
  for (int v : loop.vertices) on_loop[v] = 1;
  std::vector<int> faces;
  for (int f = 0; f < mesh.face_count(); ++f) {
    const Tri& face = mesh.faces[f];
    for (int v : face)
      if (v < 0 || v >= mesh.vertex_count())
        throw BadFaceError(source + ": face " + std::to_string(f) + " has vertex index " +
                           std::to_string(v) + " out of range");
    if (on_loop[face[0]] || on_loop[face[1]] || on_loop[face[2]]) faces.push_back(f);
  }
  return make_strip(mesh, loop, faces, source, not_a_disk);
}

Strip extract_strip(const Mesh& mesh, const VertexFaces& vertex_faces, const BoundaryLoop& loop,
                    const std::string& source) {
  if (vertex_faces.vertex_count() != mesh.vertex_count())
    throw InternalError(source + ": extract_strip was given the vertex faces of " +
                        std::to_string(vertex_faces.vertex_count()) + " vertices for a mesh of " +
                        std::to_string(mesh.vertex_count()));
  const LoopRefusal not_a_disk{source, loop.id};
  check_loop(mesh, loop, not_a_disk);
  std::vector<int> faces;
  for (int v : loop.vertices)
    faces.insert(faces.end(), vertex_faces.faces.begin() + vertex_faces.start[v],
                 vertex_faces.faces.begin() + vertex_faces.start[v + 1]);
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  return make_strip(mesh, loop, faces, source, not_a_disk);
}

namespace {

void check_strip(const Strip& strip, const std::string& source) {
  if (strip.loop_size < 3 || strip.positions.size() < static_cast<size_t>(strip.loop_size) ||
      strip.faces.empty())
    throw InternalError(source + ": flatten_strip was given an empty strip");
}

}  // namespace

Flattening flatten_strip(const Strip& strip, const std::string& source) {
  check_strip(strip, source);
  Flattening flat;
  const double pin_distance = norm(sub(strip.positions[1], strip.positions[0]));
  flat.uv = solve_lscm(strip, {{0, 0}, {pin_distance, 0}}, source);
  make_counter_clockwise(strip, flat.uv);
  measure_fit(strip, flat);
  flat.flipped_triangles = count_flipped(strip, flat.uv);
  flat.simple_polygon = is_simple(hole_polygon(strip, flat));
  if (flat.flipped_triangles > 0)
    throw FillFailedError(source + ": flattening has " + std::to_string(flat.flipped_triangles) +
                          " flipped or degenerate triangles (of " +
                          std::to_string(strip.faces.size()) + " in the strip)");
  if (!flat.simple_polygon)
    throw FillFailedError(source + ": the flattened hole outline crosses itself");
  // The strip lies to the right of the loop, so a clockwise outline has the
  // surface inside it: the loop is an outer edge.
  if (!is_counter_clockwise(hole_polygon(strip, flat)))
    throw FillFailedError(source +
                          ": the flattened loop runs clockwise, so the surface "
                          "lies inside it: it is an outer edge, not a hole");
  return flat;
}

namespace {

// The loop's polygon walked from its 3D edge lengths and exterior angles
// `turn` (radians, left positive), closed by spreading the gap along its
// length.
std::vector<Vec2> walk_polygon(const std::vector<double>& lengths,
                               const std::vector<double>& turn) {
  const int n = static_cast<int>(lengths.size());
  std::vector<Vec2> polygon(n);
  double direction = 0, along = 0;
  const double total = std::accumulate(lengths.begin(), lengths.end(), 0.0);
  Vec2 p{0, 0};
  std::vector<double> arc(n);
  for (int k = 0; k < n; ++k) {
    polygon[k] = p;
    arc[k] = along;
    // The edge from vertex k turns by the exterior angle at k (none at 0).
    if (k > 0) direction += turn[k];
    p = {p[0] + lengths[k] * std::cos(direction), p[1] + lengths[k] * std::sin(direction)};
    along += lengths[k];
  }
  for (int k = 0; k < n; ++k)
    for (int c = 0; c < 2; ++c) polygon[k][c] -= p[c] * arc[k] / total;
  return polygon;
}

}  // namespace

Flattening flatten_strip_repaired(const Strip& strip, const std::string& source) {
  check_strip(strip, source);
  const int n = strip.loop_size;
  std::vector<double> lengths(n), angle_sum(n, 0);
  for (int k = 0; k < n; ++k)
    lengths[k] = norm(sub(strip.positions[(k + 1) % n], strip.positions[k]));
  for (const Tri& f : strip.faces)
    for (int k = 0; k < 3; ++k)
      if (f[k] < n)
        angle_sum[f[k]] += corner_angle(strip.positions[f[k]], strip.positions[f[(k + 1) % 3]],
                                        strip.positions[f[(k + 2) % 3]]);
  const double total = std::accumulate(lengths.begin(), lengths.end(), 0.0);
  // The share of the turning each vertex gets on a circle of the loop's
  // length: half its two edges.
  std::vector<double> share(n);
  for (int k = 0; k < n; ++k) share[k] = 0.5 * (lengths[(k + n - 1) % n] + lengths[k]) / total;
  // The loop's own exterior angles (the strip's angle sum - pi at each
  // vertex), blended with a circle's by `blend`, then made to close (sum 2
  // pi), the difference spread like the circle's.
  const auto outline = [&](double blend) {
    std::vector<double> turn(n);
    double sum = 0;
    for (int k = 0; k < n; ++k) {
      turn[k] = (1 - blend) * (angle_sum[k] - M_PI) + blend * 2 * M_PI * share[k];
      sum += turn[k];
    }
    for (int k = 0; k < n; ++k) turn[k] += (2 * M_PI - sum) * share[k];
    return walk_polygon(lengths, turn);
  };
  for (int step = 0; step <= kRepairSteps; ++step) {
    std::vector<Vec2> polygon = outline(static_cast<double>(step) / kRepairSteps);
    if (!is_simple(polygon) || !is_counter_clockwise(polygon)) continue;
    Flattening flat;
    flat.uv = solve_lscm(strip, polygon, source);
    measure_fit(strip, flat);
    flat.flipped_triangles = count_flipped(strip, flat.uv);
    flat.simple_polygon = true;
    if (flat.flipped_triangles == 0) return flat;
  }
  throw FillFailedError(source +
                        ": no outline of the loop's edge lengths flattens its strip unflipped");
}

std::vector<Vec2> hole_polygon(const Strip& strip, const Flattening& flat) {
  if (flat.uv.size() < static_cast<size_t>(strip.loop_size))
    throw InternalError("hole_polygon: the flattening is not the strip's");
  return std::vector<Vec2>(flat.uv.begin(), flat.uv.begin() + strip.loop_size);
}

}  // namespace foldfill
