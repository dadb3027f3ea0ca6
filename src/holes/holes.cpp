// Boundary loops of a triangle mesh, their classification (holes, outer
// edges, tube ends: see holes.h) and the choice of the loops to fill.
//
// Everything is found vertex by vertex from the faces around each vertex
// (VertexFaces, compressed rows), so the memory beyond the mesh is that index
// and the boundary, not a table of all edges. The faces around each vertex
// are grouped into fans (faces linked through the edges they share at that
// vertex). A vertex with several fans is non-manifold unless all of them are
// open, in which case the boundary passes it several times; pairing each
// incoming boundary half-edge with the outgoing one of the same fan keeps
// every traced loop a chain that turns around a single fan at each visit.
#include "foldfill/holes.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <numeric>
#include <queue>
#include <string>
#include <utility>

#include "foldfill/error.h"
#include "foldfill/topology.h"

namespace foldfill {
namespace {

// One face around a vertex v: the face has the edges v -> next and previous -> v.
struct Corner {
  int face, corner;  // faces[face][corner] == v
  int next, previous;
};

// The corners at `v`, in face order.
void corners_at(const std::vector<Tri>& faces, const VertexFaces& vertex_faces, int v,
                std::vector<Corner>& corners) {
  corners.clear();
  for (int i = vertex_faces.start[v]; i < vertex_faces.start[v + 1]; ++i) {
    const int f = vertex_faces.faces[i];
    const Tri& face = faces[f];
    const int k = face[0] == v ? 0 : face[1] == v ? 1 : 2;
    corners.push_back({f, k, face[(k + 1) % 3], face[(k + 2) % 3]});
  }
}

// A boundary half-edge from -> to, along the missing side of `face`'s edge.
struct BoundaryHalfEdge {
  int from, to, face;
};

// Checks every edge (at most two faces, used in opposite directions) and
// returns the boundary half-edges in edge order.
std::vector<BoundaryHalfEdge> check_edges(const std::vector<Tri>& faces,
                                          const VertexFaces& vertex_faces,
                                          const std::string& source) {
  std::vector<BoundaryHalfEdge> boundary;
  std::vector<Edge> edges;
  for (int v = 0; v < vertex_faces.vertex_count(); ++v) {
    edges_from_vertex(faces, vertex_faces, v, edges, source);
    for (const Edge& edge : edges) {
      if (edge.face[1] < 0) boundary.push_back({edge.v1, edge.v0, edge.face[0]});
      if (edge.face[0] < 0) boundary.push_back({edge.v0, edge.v1, edge.face[1]});
    }
  }
  return boundary;
}

// Groups `corners` (of one vertex v) into fans, faces joined across the
// edges they share at v: fan[i] is the fan of corners[i]. Returns the count.
// The face with v -> w is joined to the one with w -> v (check_edges made it
// unique), found by binary search so that a vertex of high degree costs
// O(d log d).
int group_into_fans(const std::vector<Corner>& corners,
                    std::vector<std::pair<int, int>>& by_previous, std::vector<int>& fan) {
  const int n = static_cast<int>(corners.size());
  by_previous.clear();
  for (int i = 0; i < n; ++i) by_previous.emplace_back(corners[i].previous, i);
  std::sort(by_previous.begin(), by_previous.end());
  fan.resize(n);
  std::iota(fan.begin(), fan.end(), 0);
  const auto root = [&](int i) {
    while (fan[i] != i) i = fan[i] = fan[fan[i]];
    return i;
  };
  for (int i = 0; i < n; ++i) {
    const auto j =
        std::lower_bound(by_previous.begin(), by_previous.end(), std::pair(corners[i].next, -1));
    if (j != by_previous.end() && j->first == corners[i].next) fan[root(i)] = root(j->second);
  }
  int count = 0;
  for (int i = 0; i < n; ++i) count += root(i) == i;
  for (int i = 0; i < n; ++i) fan[i] = root(i);
  return count;
}

// The boundary half-edges chained into loops, and the vertices where the
// boundary passes more than once.
struct LinkedBoundary {
  std::vector<int> next;      // next[h]: the boundary half-edge after h
  std::vector<char> pinched;  // per vertex
};

// Pairs, at every vertex, each incoming boundary half-edge with the outgoing
// one of the same fan; throws for a vertex with several fans one of which is
// closed (a vertex with several fans, all open, is pinched).
LinkedBoundary link_boundary(const std::vector<Tri>& faces, const VertexFaces& vertex_faces,
                             const std::vector<BoundaryHalfEdge>& boundary,
                             const std::string& source) {
  const int vertex_count = vertex_faces.vertex_count();
  // Boundary half-edges by `from` and by `to` (compressed rows).
  std::vector<int> out_start(vertex_count + 1, 0), in_start(vertex_count + 1, 0);
  for (const BoundaryHalfEdge& h : boundary) {
    ++out_start[h.from + 1];
    ++in_start[h.to + 1];
  }
  for (int v = 0; v < vertex_count; ++v) {
    out_start[v + 1] += out_start[v];
    in_start[v + 1] += in_start[v];
  }
  std::vector<int> outgoing(boundary.size()), incoming(boundary.size());
  {
    std::vector<int> out_cursor(out_start.begin(), out_start.end() - 1);
    std::vector<int> in_cursor(in_start.begin(), in_start.end() - 1);
    for (size_t h = 0; h < boundary.size(); ++h) {
      outgoing[out_cursor[boundary[h].from]++] = static_cast<int>(h);
      incoming[in_cursor[boundary[h].to]++] = static_cast<int>(h);
    }
  }

  LinkedBoundary linked{std::vector<int>(boundary.size(), -1), std::vector<char>(vertex_count, 0)};
  std::vector<Corner> corners;
  std::vector<std::pair<int, int>> by_previous;
  std::vector<int> fan, outgoing_of_fan;
  for (int v = 0; v < vertex_count; ++v) {
    corners_at(faces, vertex_faces, v, corners);
    const int fan_count = group_into_fans(corners, by_previous, fan);
    const int open_fans = out_start[v + 1] - out_start[v];  // one boundary half-edge out of each
    if (fan_count > 1 && open_fans < fan_count)
      throw NonManifoldError(source + ": vertex " + std::to_string(v) +
                             " is non-manifold (its faces form " + std::to_string(fan_count) +
                             " separate fans)");
    linked.pinched[v] = fan_count > 1;
    // Corners are in face order.
    const auto fan_of_face = [&](int face) {
      const auto corner = std::lower_bound(corners.begin(), corners.end(), face,
                                           [](const Corner& c, int f) { return c.face < f; });
      return fan[corner - corners.begin()];
    };
    outgoing_of_fan.assign(corners.size(), -1);
    for (int k = out_start[v]; k < out_start[v + 1]; ++k)
      outgoing_of_fan[fan_of_face(boundary[outgoing[k]].face)] = outgoing[k];
    for (int k = in_start[v]; k < in_start[v + 1]; ++k) {
      const int h = incoming[k];
      linked.next[h] = outgoing_of_fan[fan_of_face(boundary[h].face)];
      if (linked.next[h] < 0)
        throw InternalError(source + ": boundary at vertex " + std::to_string(v) +
                            " has no outgoing edge");
    }
  }
  return linked;
}

// Follows `next` from every unvisited half-edge; each cycle is a vertex list
// starting at its smallest vertex.
std::vector<std::vector<int>> trace_cycles(const std::vector<BoundaryHalfEdge>& half_edges,
                                           const std::vector<int>& next,
                                           const std::string& source) {
  std::vector<std::vector<int>> cycles;
  std::vector<char> visited(half_edges.size(), 0);
  for (size_t start = 0; start < half_edges.size(); ++start) {
    if (visited[start]) continue;
    std::vector<int> vertices;
    int h = static_cast<int>(start);
    for (; !visited[h]; h = next[h]) {
      visited[h] = 1;
      vertices.push_back(half_edges[h].from);
    }
    if (h != static_cast<int>(start)) {
      throw InternalError(source + ": boundary chain from vertex " +
                          std::to_string(vertices.front()) + " does not close");
    }
    cycles.push_back(std::move(vertices));
  }
  return cycles;
}

// A boundary cycle that passes a pinched vertex more than once (a hole that
// touches the outer edge or another hole at one vertex) split there into
// simple cycles, each the boundary of one missing piece: walking the cycle,
// the part between two visits of a vertex is closed off as a cycle of its
// own. `position` (per vertex, all -1) is scratch space, left all -1.
void split_at_repeated_vertices(const std::vector<int>& cycle, std::vector<int>& position,
                                std::vector<std::vector<int>>& simple_cycles) {
  std::vector<int> path;
  for (int v : cycle) {
    if (position[v] < 0) {
      position[v] = static_cast<int>(path.size());
      path.push_back(v);
      continue;
    }
    const auto from = path.begin() + position[v];
    for (auto it = from + 1; it != path.end(); ++it) position[*it] = -1;
    simple_cycles.emplace_back(from, path.end());
    path.erase(from + 1, path.end());
  }
  for (int v : path) position[v] = -1;
  simple_cycles.push_back(std::move(path));
}

// The cycles of `traced`, those through pinched vertices split into simple
// ones, each starting at its smallest vertex, sorted; `origin[i]` is the
// traced cycle that simple cycle i came from.
std::vector<std::vector<int>> simple_cycles(const std::vector<std::vector<int>>& traced,
                                            const std::vector<char>& pinched,
                                            std::vector<int>& origin) {
  std::vector<std::pair<std::vector<int>, int>> cycles;
  std::vector<int> position;
  std::vector<std::vector<int>> pieces;
  for (size_t c = 0; c < traced.size(); ++c) {
    const std::vector<int>& cycle = traced[c];
    pieces.clear();
    if (std::any_of(cycle.begin(), cycle.end(), [&](int v) { return pinched[v] != 0; })) {
      position.resize(pinched.size(), -1);
      split_at_repeated_vertices(cycle, position, pieces);
    } else {
      pieces.push_back(cycle);
    }
    for (std::vector<int>& piece : pieces) {
      std::rotate(piece.begin(), std::min_element(piece.begin(), piece.end()), piece.end());
      cycles.emplace_back(std::move(piece), static_cast<int>(c));
    }
  }
  std::sort(cycles.begin(), cycles.end());
  std::vector<std::vector<int>> result;
  origin.clear();
  for (auto& [cycle, from] : cycles) {
    result.push_back(std::move(cycle));
    origin.push_back(from);
  }
  return result;
}

double distance(const Vec3& a, const Vec3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

// `value` with `digits` significant digits (0: rounded to a whole number), as
// messages print it.
std::string format_number(double value, int digits = 3) {
  if (std::isinf(value)) return value > 0 ? "infinity" : "-infinity";
  char text[64];
  if (digits == 0) {
    std::snprintf(text, sizeof text, "%.0f", std::round(value) == 0 ? 0.0 : value);
  } else {
    std::snprintf(text, sizeof text, "%.*g", digits, value);
  }
  return text;
}

std::string format_point(const Vec3& p) {
  return "(" + format_number(p[0], 6) + ", " + format_number(p[1], 6) + ", " +
         format_number(p[2], 6) + ")";
}

// The angle at `p` between the directions to `a` and `b`, in [0, pi]. Edges
// so short or long that their products would underflow or overflow are
// scaled by a power of two first (exactly), so that the angle is the same at
// any unit.
double corner_angle(const Vec3& p, const Vec3& a, const Vec3& b) {
  Vec3 u{a[0] - p[0], a[1] - p[1], a[2] - p[2]}, w{b[0] - p[0], b[1] - p[1], b[2] - p[2]};
  const double largest = std::max({std::abs(u[0]), std::abs(u[1]), std::abs(u[2]), std::abs(w[0]),
                                   std::abs(w[1]), std::abs(w[2])});
  if (largest > 0 && std::isfinite(largest) && (largest < 1e-100 || largest > 1e100)) {
    const int exponent = -std::ilogb(largest);
    for (double& x : u) x = std::ldexp(x, exponent);
    for (double& x : w) x = std::ldexp(x, exponent);
  }
  const Vec3 cross{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
  return std::atan2(std::hypot(cross[0], cross[1], cross[2]),
                    u[0] * w[0] + u[1] * w[1] + u[2] * w[2]);
}

// Sum of the face angles at each vertex in `wanted` (others stay 0): one pass
// over the faces, angles computed only at the wanted corners.
std::vector<double> angle_sums(const Mesh& mesh, const std::vector<char>& wanted) {
  std::vector<double> sums(mesh.positions.size(), 0.0);
  for (const Tri& f : mesh.faces) {
    for (int k = 0; k < 3; ++k) {
      if (!wanted[f[k]]) continue;
      sums[f[k]] += corner_angle(mesh.positions[f[k]], mesh.positions[f[(k + 1) % 3]],
                                 mesh.positions[f[(k + 2) % 3]]);
    }
  }
  return sums;
}

void measure_turning(const Mesh& mesh, std::vector<BoundaryLoop>& loops) {
  std::vector<char> on_loop(mesh.positions.size(), 0);
  for (const BoundaryLoop& loop : loops) {
    for (int v : loop.vertices) on_loop[v] = 1;
  }
  const std::vector<double> sums = angle_sums(mesh, on_loop);
  for (BoundaryLoop& loop : loops) {
    const size_t n = loop.vertices.size();
    for (size_t k = 0; k < n; ++k) {
      const int v = loop.vertices[k];
      const bool split =
          std::find(loop.split_at.begin(), loop.split_at.end(), v) != loop.split_at.end();
      // The faces at a vertex where the boundary was split lie around several
      // missing pieces: the loop's own turns by pi less the angle between its
      // edges there (as where the surface around it is flat).
      loop.turning += split
                          ? M_PI - corner_angle(loop.positions[k], loop.positions[(k + n - 1) % n],
                                                loop.positions[(k + 1) % n])
                          : sums[v] - M_PI;
    }
  }
}

BoundaryLoop make_loop(int id, std::vector<int> vertices, const std::vector<Vec3>& positions) {
  BoundaryLoop loop;
  loop.id = id;
  loop.vertices = std::move(vertices);
  const size_t n = loop.vertices.size();
  loop.positions.reserve(n);
  for (int v : loop.vertices) loop.positions.push_back(positions[v]);

  Vec3 low = loop.positions[0], high = loop.positions[0];
  for (size_t i = 0; i < n; ++i) {
    const Vec3& p = loop.positions[i];
    loop.length += distance(p, loop.positions[(i + 1) % n]);
    for (int c = 0; c < 3; ++c) {
      loop.centroid[c] += p[c];
      low[c] = std::min(low[c], p[c]);
      high[c] = std::max(high[c], p[c]);
    }
  }
  for (double& c : loop.centroid) c /= static_cast<double>(n);
  loop.bbox_diagonal = distance(low, high);
  loop.mean_edge_length = loop.length / static_cast<double>(n);
  return loop;
}

// At each pinched vertex of a loop: the loops split from the same boundary
// cycle share it (`split_at`); a loop from another cycle there (two pieces of
// surface that meet at a point) makes the loop not a disk, naming the first
// such vertex along it and the other loop.
void flag_pinched_loops(std::vector<BoundaryLoop>& loops, const std::vector<int>& origin,
                        const std::vector<char>& pinched) {
  struct Visit {
    int vertex, loop;
    bool operator<(const Visit& rhs) const {
      return std::pair(vertex, loop) < std::pair(rhs.vertex, rhs.loop);
    }
  };
  std::vector<Visit> visits;
  for (const BoundaryLoop& loop : loops) {
    for (int v : loop.vertices) {
      if (pinched[v]) visits.push_back({v, loop.id});
    }
  }
  std::sort(visits.begin(), visits.end());

  for (BoundaryLoop& loop : loops) {
    for (int v : loop.vertices) {
      if (!pinched[v]) continue;
      const auto begin = std::lower_bound(visits.begin(), visits.end(), Visit{v, -1});
      const auto end = std::lower_bound(visits.begin(), visits.end(), Visit{v + 1, -1});
      const auto other = std::find_if(
          begin, end, [&](const Visit& visit) { return origin[visit.loop] != origin[loop.id]; });
      if (other == end) {
        loop.split_at.push_back(v);
      } else if (loop.is_disk) {
        loop.is_disk = false;
        loop.reason =
            "touches loop " + std::to_string(other->loop) + " at vertex " + std::to_string(v);
      }
    }
  }
}

double distance_to_segment(const Vec3& p, const Vec3& a, const Vec3& b) {
  Vec3 ab{}, ap{};
  double ab2 = 0, t = 0;
  for (int c = 0; c < 3; ++c) {
    ab[c] = b[c] - a[c];
    ap[c] = p[c] - a[c];
    ab2 += ab[c] * ab[c];
    t += ab[c] * ap[c];
  }
  t = ab2 > 0 ? std::clamp(t / ab2, 0.0, 1.0) : 0.0;
  return distance(p, {a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]});
}

double distance_to_loop(const Vec3& p, const BoundaryLoop& loop, const std::string& source) {
  const size_t n = loop.positions.size();
  if (n == 0 || n != loop.vertices.size()) {
    throw InternalError(source + ": loop " + std::to_string(loop.id) +
                        " has no positions (not from find_boundary_loops)");
  }
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < n; ++i) {
    best = std::min(best, distance_to_segment(p, loop.positions[i], loop.positions[(i + 1) % n]));
  }
  return best;
}

// The loop closest to `point`. Throws UsageError when the point is farther
// from every loop than that loop's bounding-box diagonal (it names no loop).
int nearest_loop(const std::vector<BoundaryLoop>& loops, const Vec3& point,
                 const std::string& source) {
  if (loops.empty()) {
    throw UsageError(source + ": no loop to select near a point (the mesh has no boundary)");
  }
  int best = 0;
  double best_distance = std::numeric_limits<double>::infinity();
  bool within_a_loop = false;
  for (size_t i = 0; i < loops.size(); ++i) {
    const double d = distance_to_loop(point, loops[i], source);
    within_a_loop |= d <= loops[i].bbox_diagonal;
    if (d < best_distance) {
      best_distance = d;
      best = static_cast<int>(i);
    }
  }
  if (!within_a_loop) {
    throw UsageError(source + ": no loop near the point " + format_point(point) +
                     ": the nearest, loop " + std::to_string(best) + ", is " +
                     format_number(best_distance) + " away, farther than its size (" +
                     format_number(loops[best].bbox_diagonal) + ")");
  }
  return best;
}

std::string not_a_disk(const BoundaryLoop& loop) {
  return "loop " + std::to_string(loop.id) + " is not a disk boundary (" + loop.reason + ")";
}

// The loops named explicitly (ids, and the nearest loop of each point): all
// must exist and be disks.
std::vector<int> named_loops(const std::vector<BoundaryLoop>& loops, const HoleSelection& selection,
                             const std::string& source) {
  std::vector<int> ids = selection.ids;
  if (selection.mode == HoleSelection::Mode::Near) {
    for (const Vec3& point : selection.near) ids.push_back(nearest_loop(loops, point, source));
  }
  for (int id : ids) {
    if (id < 0 || id >= static_cast<int>(loops.size())) {
      throw UsageError(source + ": no loop with id " + std::to_string(id) + " (the mesh has " +
                       std::to_string(loops.size()) + " loops)");
    }
    if (!loops[id].is_disk) throw NotADiskError(source + ": " + not_a_disk(loops[id]));
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

// Per vertex of a mesh: the sum of its face angles and a third of the area of
// its faces; per vertex, its connected piece of surface, and per piece its
// area.
struct SurfaceMeasures {
  std::vector<double> angle_sum, vertex_area;
  std::vector<int> piece;
  std::vector<double> piece_area;
};

SurfaceMeasures measure_surface(const Mesh& mesh) {
  const int n = mesh.vertex_count();
  SurfaceMeasures m{
      std::vector<double>(n, 0.0), std::vector<double>(n, 0.0), std::vector<int>(n), {}};
  std::iota(m.piece.begin(), m.piece.end(), 0);
  const auto root = [&](int v) {
    while (m.piece[v] != v) v = m.piece[v] = m.piece[m.piece[v]];
    return v;
  };
  std::vector<double> face_area(mesh.faces.size());
  for (size_t f = 0; f < mesh.faces.size(); ++f) {
    const Tri& t = mesh.faces[f];
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const Vec3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, w{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    face_area[f] = 0.5 * std::hypot(u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                                    u[0] * w[1] - u[1] * w[0]);
    for (int k = 0; k < 3; ++k) {
      m.angle_sum[t[k]] += corner_angle(mesh.positions[t[k]], mesh.positions[t[(k + 1) % 3]],
                                        mesh.positions[t[(k + 2) % 3]]);
      m.vertex_area[t[k]] += face_area[f] / 3;
    }
    m.piece[root(t[1])] = root(t[0]);
    m.piece[root(t[2])] = root(t[0]);
  }
  for (int v = 0; v < n; ++v) m.piece[v] = root(v);
  m.piece_area.assign(n, 0.0);
  for (size_t f = 0; f < mesh.faces.size(); ++f)
    m.piece_area[m.piece[mesh.faces[f][0]]] += face_area[f];
  return m;
}

// The curvature density around `loop`: the angle defects of the interior
// vertices within `radius` of it (along the edges, by Dijkstra from all its
// vertices) over their area; 0 where there are none. `distance` (per vertex,
// all infinite) is scratch space, left all infinite.
double curvature_near(const Mesh& mesh, const VertexFaces& vertex_faces,
                      const SurfaceMeasures& measures, const std::vector<char>& on_boundary,
                      const BoundaryLoop& loop, double radius, std::vector<double>& band) {
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  std::vector<int> reached;
  for (int v : loop.vertices) {
    band[v] = 0;
    reached.push_back(v);
    queue.push({0.0, v});
  }
  double defect = 0, area = 0;
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > band[v]) continue;
    if (!on_boundary[v]) {
      defect += 2 * M_PI - measures.angle_sum[v];
      area += measures.vertex_area[v];
    }
    for (int i = vertex_faces.start[v]; i < vertex_faces.start[v + 1]; ++i) {
      for (int w : mesh.faces[vertex_faces.faces[i]]) {
        const double through = d + distance(mesh.positions[v], mesh.positions[w]);
        if (through > radius || through >= band[w]) continue;
        if (std::isinf(band[w])) reached.push_back(w);
        band[w] = through;
        queue.push({through, w});
      }
    }
  }
  for (int v : reached) band[v] = std::numeric_limits<double>::infinity();
  return area > 0 ? defect / area : 0.0;
}
}  // namespace

std::vector<BoundaryLoop> find_boundary_loops(const Mesh& mesh, const std::string& source) {
  const VertexFaces vertex_faces = build_vertex_faces(mesh.faces, mesh.vertex_count(), source);
  const std::vector<BoundaryHalfEdge> half_edges = check_edges(mesh.faces, vertex_faces, source);
  const LinkedBoundary linked = link_boundary(mesh.faces, vertex_faces, half_edges, source);

  std::vector<int> origin;
  std::vector<std::vector<int>> cycles =
      simple_cycles(trace_cycles(half_edges, linked.next, source), linked.pinched, origin);
  std::vector<BoundaryLoop> loops;
  loops.reserve(cycles.size());
  for (auto& cycle : cycles) {
    loops.push_back(make_loop(static_cast<int>(loops.size()), std::move(cycle), mesh.positions));
  }
  flag_pinched_loops(loops, origin, linked.pinched);
  measure_turning(mesh, loops);
  classify_loops(mesh, loops);
  return loops;
}

void classify_loops(const Mesh& mesh, std::vector<BoundaryLoop>& loops,
                    const ClassifyOptions& options) {
  if (loops.empty()) return;
  const SurfaceMeasures measures = measure_surface(mesh);
  const VertexFaces vertex_faces = build_vertex_faces(mesh.faces, mesh.vertex_count());
  std::vector<char> on_boundary(mesh.positions.size(), 0);
  for (const BoundaryLoop& loop : loops) {
    for (int v : loop.vertices) on_boundary[v] = 1;
  }
  std::vector<double> scratch(mesh.positions.size(), std::numeric_limits<double>::infinity());
  for (BoundaryLoop& loop : loops) {
    loop.component_area = measures.piece_area[measures.piece[loop.vertices.front()]];
    const double radius =
        std::max(options.band * loop.bbox_diagonal, options.band_edges * loop.mean_edge_length);
    loop.curvature_density =
        curvature_near(mesh, vertex_faces, measures, on_boundary, loop, radius, scratch);
    loop.predicted_area = loop.curvature_density > 0
                              ? (2 * M_PI - loop.turning) / loop.curvature_density
                              : std::numeric_limits<double>::infinity();
    const auto set = [&](LoopKind kind, LoopKindReason reason) {
      loop.kind = kind;
      loop.kind_reason = reason;
    };
    if (!loop.is_disk) {
      set(LoopKind::NotADisk, LoopKindReason::TouchesAnotherPiece);
    } else if (loop.turning > options.hole_turning) {
      set(LoopKind::Hole, LoopKindReason::TurnsLikeAHole);
    } else if (loop.predicted_area < loop.component_area) {
      set(LoopKind::Hole, LoopKindReason::ClosesTheCurvature);
    } else if (loop.turning < options.edge_turning) {
      set(LoopKind::OuterEdge, LoopKindReason::TurnsLikeAnEdge);
    } else {
      set(LoopKind::TubeEnd, LoopKindReason::TurnsLikeATubeEnd);
    }
  }
}

const char* to_string(LoopKind kind) {
  switch (kind) {
    case LoopKind::Hole:
      return "hole";
    case LoopKind::OuterEdge:
      return "outer edge";
    case LoopKind::TubeEnd:
      return "tube end";
    case LoopKind::NotADisk:
      return "not a disk";
  }
  return "?";
}

const char* json_name(LoopKind kind) {
  switch (kind) {
    case LoopKind::Hole:
      return "hole";
    case LoopKind::OuterEdge:
      return "outer_edge";
    case LoopKind::TubeEnd:
      return "tube_end";
    case LoopKind::NotADisk:
      return "not_a_disk";
  }
  return "?";
}

const char* json_name(LoopKindReason reason) {
  switch (reason) {
    case LoopKindReason::TurnsLikeAHole:
      return "turns_like_a_hole";
    case LoopKindReason::ClosesTheCurvature:
      return "closes_the_curvature";
    case LoopKindReason::TurnsLikeAnEdge:
      return "turns_like_an_edge";
    case LoopKindReason::TurnsLikeATubeEnd:
      return "turns_like_a_tube_end";
    case LoopKindReason::TouchesAnotherPiece:
      return "touches_another_piece";
  }
  return "?";
}

std::string explain_kind(const BoundaryLoop& loop) {
  const std::string turns = "turns by " + format_number(loop.turning * 180 / M_PI, 0) + " degrees";
  const std::string curvature = "the surrounding curvature (K " +
                                format_number(loop.curvature_density) +
                                ") closes it with an area of " + format_number(loop.predicted_area);
  const std::string present = format_number(loop.component_area) + " present";
  // Why the curvature does not make an edge a hole, where it is positive.
  const std::string not_closing =
      loop.curvature_density > 0 ? ", and " + curvature + ", not less than the " + present : "";
  switch (loop.kind_reason) {
    case LoopKindReason::TurnsLikeAHole:
      return turns + ", more than 180, like the edge of a missing piece";
    case LoopKindReason::ClosesTheCurvature:
      return turns + ", but " + curvature + ", less than the " + present;
    case LoopKindReason::TurnsLikeAnEdge:
      return turns + ", like a sheet's outer edge" + not_closing;
    case LoopKindReason::TurnsLikeATubeEnd:
      return turns + ", like the end of a tube" + not_closing;
    case LoopKindReason::TouchesAnotherPiece:
      return "is not a disk boundary (" + loop.reason + ")";
  }
  return "";
}

const char* to_string(ChoiceReason reason) {
  switch (reason) {
    case ChoiceReason::IsAHole:
      return "a hole";
    case ChoiceReason::Named:
      return "named";
    case ChoiceReason::NotLongest:
      return "not among the longest";
    case ChoiceReason::NotAHole:
      return "not a hole";
    case ChoiceReason::NotADisk:
      return "not a disk boundary";
    case ChoiceReason::NotNamed:
      return "not named";
    case ChoiceReason::Longest:
      return "among the longest";
    case ChoiceReason::TooManyEdges:
      return "too many edges";
    case ChoiceReason::TooWide:
      return "too wide";
  }
  return "?";
}

const char* json_name(ChoiceReason reason) {
  switch (reason) {
    case ChoiceReason::IsAHole:
      return "is_a_hole";
    case ChoiceReason::Named:
      return "named";
    case ChoiceReason::NotLongest:
      return "not_longest";
    case ChoiceReason::NotAHole:
      return "not_a_hole";
    case ChoiceReason::NotADisk:
      return "not_a_disk";
    case ChoiceReason::NotNamed:
      return "not_named";
    case ChoiceReason::Longest:
      return "longest";
    case ChoiceReason::TooManyEdges:
      return "too_many_edges";
    case ChoiceReason::TooWide:
      return "too_wide";
  }
  return "?";
}

std::vector<int> longest_loops(const std::vector<BoundaryLoop>& loops, int count) {
  std::vector<int> order(loops.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return loops[a].length > loops[b].length; });
  order.resize(std::min(order.size(), static_cast<size_t>(std::max(count, 0))));
  std::sort(order.begin(), order.end());
  return order;
}

bool turns_like_a_hole(const BoundaryLoop& loop) { return loop.turning > M_PI; }

double mean_edge_length(const Mesh& mesh) {
  const EdgeTopology topology = build_edge_topology(mesh.faces, mesh.vertex_count());
  double sum = 0;
  for (const Edge& e : topology.edges) sum += distance(mesh.positions[e.v0], mesh.positions[e.v1]);
  return topology.edges.empty() ? 0.0 : sum / static_cast<double>(topology.edges.size());
}

HoleChoice select_holes(const std::vector<BoundaryLoop>& loops, const HoleSelection& selection,
                        const std::string& source) {
  using Mode = HoleSelection::Mode;
  const size_t n = loops.size();
  HoleChoice choice;
  choice.reasons.assign(n, ChoiceReason::NotNamed);
  const auto skip_not_a_disk = [&](size_t id) {
    choice.reasons[id] = ChoiceReason::NotADisk;
    choice.warnings.push_back(not_a_disk(loops[id]) + ": left open");
  };
  if (selection.mode == Mode::Ids || selection.mode == Mode::Near) {
    for (int id : named_loops(loops, selection, source)) choice.reasons[id] = ChoiceReason::Named;
  } else if (selection.mode == Mode::KeepOpen) {
    std::vector<char> longest(n, 0);
    for (int id : longest_loops(loops, selection.keep_open)) longest[id] = 1;
    for (size_t id = 0; id < n; ++id) {
      if (longest[id]) {
        choice.reasons[id] = ChoiceReason::Longest;
      } else if (!loops[id].is_disk) {
        skip_not_a_disk(id);
      } else {
        choice.reasons[id] = ChoiceReason::NotLongest;
      }
    }
  } else {
    for (size_t id = 0; id < n; ++id) {
      if (loops[id].kind == LoopKind::NotADisk) {
        skip_not_a_disk(id);
      } else {
        choice.reasons[id] =
            loops[id].kind == LoopKind::Hole ? ChoiceReason::IsAHole : ChoiceReason::NotAHole;
      }
    }
  }
  for (size_t id = 0; id < n; ++id) {
    ChoiceReason& reason = choice.reasons[id];
    const bool chosen = reason == ChoiceReason::IsAHole || reason == ChoiceReason::Named ||
                        reason == ChoiceReason::NotLongest;
    if (chosen && selection.max_hole_size > 0 &&
        loops[id].vertices.size() > static_cast<size_t>(selection.max_hole_size)) {
      reason = ChoiceReason::TooManyEdges;
    } else if (chosen && selection.max_hole_diameter > 0 &&
               loops[id].bbox_diagonal > selection.max_hole_diameter) {
      reason = ChoiceReason::TooWide;
    }
    const bool fill = reason == ChoiceReason::IsAHole || reason == ChoiceReason::Named ||
                      reason == ChoiceReason::NotLongest;
    (fill ? choice.fill : choice.left_open).push_back(static_cast<int>(id));
  }
  return choice;
}
}  // namespace foldfill
