// Boundary loops of a triangle mesh and the choice of the loops to fill.
//
// The faces around each vertex are grouped into fans (faces linked through the
// edges they share at that vertex) with a union-find over face corners. A
// vertex with several fans is non-manifold unless all of them are open, in
// which case the boundary passes it several times; pairing each incoming
// boundary half-edge with the outgoing one of the same fan keeps every traced
// loop a chain that turns around a single fan at each visit.
#include "foldfill/holes.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <utility>

#include "foldfill/error.h"
#include "foldfill/topology.h"

namespace foldfill {
namespace {

// The corner of `face` (index f) at vertex v: 3 f + k with faces[f][k] == v.
int corner_at(const Tri& face, int f, int v) {
  return 3 * f + (face[0] == v ? 0 : face[1] == v ? 1 : 2);
}

// Union-find over face corners; a set is one fan of faces around a vertex.
class CornerFans {
 public:
  explicit CornerFans(size_t corner_count) : parent_(corner_count) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  int find(int corner) {
    while (parent_[corner] != corner) {
      parent_[corner] = parent_[parent_[corner]];  // path halving keeps trees shallow
      corner = parent_[corner];
    }
    return corner;
  }
  void unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }
  bool is_root(int corner) const { return parent_[corner] == corner; }

 private:
  std::vector<int> parent_;
};

// Links the corners of the two faces of every interior edge at both endpoints.
CornerFans group_corners_into_fans(const std::vector<Tri>& faces, const EdgeTopology& topology) {
  CornerFans fans(faces.size() * 3);
  for (const Edge& edge : topology.edges) {
    if (edge.is_boundary()) continue;
    const Tri& f0 = faces[edge.face[0]];
    const Tri& f1 = faces[edge.face[1]];
    for (int v : {edge.v0, edge.v1}) {
      fans.unite(corner_at(f0, edge.face[0], v), corner_at(f1, edge.face[1], v));
    }
  }
  return fans;
}

// Throws for a vertex with several fans one of which is closed; returns, per
// vertex, whether it is pinched (several fans, all open).
std::vector<char> find_pinched_vertices(const std::vector<Tri>& faces, const EdgeTopology& topology,
                                        const CornerFans& fans, int vertex_count,
                                        const std::string& source) {
  std::vector<int> fan_count(vertex_count, 0), boundary_degree(vertex_count, 0);
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int k = 0; k < 3; ++k) {
      if (fans.is_root(static_cast<int>(3 * f + k))) ++fan_count[faces[f][k]];
    }
  }
  for (const Edge& edge : topology.edges) {
    if (!edge.is_boundary()) continue;
    ++boundary_degree[edge.v0];
    ++boundary_degree[edge.v1];
  }
  std::vector<char> pinched(vertex_count, 0);
  for (int v = 0; v < vertex_count; ++v) {
    if (fan_count[v] < 2) continue;
    const int open_fans = boundary_degree[v] / 2;  // an open fan has two boundary edges at v
    if (open_fans < fan_count[v]) {
      throw Error(ErrorKind::NonManifold, source + ": vertex " + std::to_string(v) +
                                              " is non-manifold (its faces form " +
                                              std::to_string(fan_count[v]) + " separate fans)");
    }
    pinched[v] = 1;
  }
  return pinched;
}

// A boundary half-edge from -> to, along the missing side of `face`'s edge.
struct BoundaryHalfEdge {
  int from, to, face;
};

std::vector<BoundaryHalfEdge> boundary_half_edges(const EdgeTopology& topology) {
  std::vector<BoundaryHalfEdge> half_edges;
  for (const Edge& edge : topology.edges) {
    if (edge.face[1] < 0) {
      half_edges.push_back({edge.v1, edge.v0, edge.face[0]});
    } else if (edge.face[0] < 0) {
      half_edges.push_back({edge.v0, edge.v1, edge.face[1]});
    }
  }
  return half_edges;
}

// next[h]: the boundary half-edge leaving h.to within the fan of h's face.
std::vector<int> link_boundary_half_edges(const std::vector<Tri>& faces,
                                          const std::vector<BoundaryHalfEdge>& half_edges,
                                          CornerFans& fans, const std::string& source) {
  std::vector<int> outgoing_of_fan(faces.size() * 3, -1);  // indexed by the fan's root corner
  for (size_t h = 0; h < half_edges.size(); ++h) {
    const BoundaryHalfEdge& he = half_edges[h];
    outgoing_of_fan[fans.find(corner_at(faces[he.face], he.face, he.from))] = static_cast<int>(h);
  }
  std::vector<int> next(half_edges.size());
  for (size_t h = 0; h < half_edges.size(); ++h) {
    const BoundaryHalfEdge& he = half_edges[h];
    next[h] = outgoing_of_fan[fans.find(corner_at(faces[he.face], he.face, he.to))];
    if (next[h] < 0) {
      throw Error(ErrorKind::Internal, source + ": boundary at vertex " + std::to_string(he.to) +
                                           " has no outgoing edge");
    }
  }
  return next;
}

// Follows `next` from every unvisited half-edge; each cycle becomes a loop's
// vertex list starting at its smallest vertex.
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
      throw Error(ErrorKind::Internal, source + ": boundary chain from vertex " +
                                           std::to_string(vertices.front()) + " does not close");
    }
    std::rotate(vertices.begin(), std::min_element(vertices.begin(), vertices.end()),
                vertices.end());
    cycles.push_back(std::move(vertices));
  }
  std::sort(cycles.begin(), cycles.end());
  return cycles;
}

double distance(const Vec3& a, const Vec3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

// Sum of the face angles at each vertex in `wanted` (others stay 0): one pass
// over the faces, angles computed only at the wanted corners.
std::vector<double> angle_sums(const Mesh& mesh, const std::vector<char>& wanted) {
  std::vector<double> sums(mesh.positions.size(), 0.0);
  for (const Tri& f : mesh.faces) {
    for (int k = 0; k < 3; ++k) {
      if (!wanted[f[k]]) continue;
      const Vec3& p = mesh.positions[f[k]];
      const Vec3& a = mesh.positions[f[(k + 1) % 3]];
      const Vec3& b = mesh.positions[f[(k + 2) % 3]];
      const Vec3 u{a[0] - p[0], a[1] - p[1], a[2] - p[2]}, w{b[0] - p[0], b[1] - p[1], b[2] - p[2]};
      const Vec3 cross{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
      sums[f[k]] += std::atan2(std::hypot(cross[0], cross[1], cross[2]),
                               u[0] * w[0] + u[1] * w[1] + u[2] * w[2]);
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
    for (int v : loop.vertices) loop.turning += sums[v] - M_PI;
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

// Marks the loops through pinched vertices as not disks, naming the first
// pinched vertex along each loop and what the loop touches there.
void flag_pinched_loops(std::vector<BoundaryLoop>& loops, const std::vector<char>& pinched) {
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
    const auto first = std::find_if(loop.vertices.begin(), loop.vertices.end(),
                                    [&](int v) { return pinched[v] != 0; });
    if (first == loop.vertices.end()) continue;
    const int v = *first;
    const auto begin = std::lower_bound(visits.begin(), visits.end(), Visit{v, -1});
    const auto end = std::lower_bound(visits.begin(), visits.end(), Visit{v + 1, -1});
    const auto own = std::equal_range(begin, end, Visit{v, loop.id});
    const auto other =
        std::find_if(begin, end, [&](const Visit& visit) { return visit.loop != loop.id; });
    loop.is_disk = false;
    if (own.second - own.first > 1 || other == end) {
      loop.reason =
          "touches itself at vertex " + std::to_string(v) + " (the surface is pinched there)";
    } else {
      loop.reason =
          "touches loop " + std::to_string(other->loop) + " at vertex " + std::to_string(v);
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
    throw Error(ErrorKind::Internal, source + ": loop " + std::to_string(loop.id) +
                                         " has no positions (not from find_boundary_loops)");
  }
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < n; ++i) {
    best = std::min(best, distance_to_segment(p, loop.positions[i], loop.positions[(i + 1) % n]));
  }
  return best;
}

int nearest_loop(const std::vector<BoundaryLoop>& loops, const Vec3& point,
                 const std::string& source) {
  if (loops.empty()) {
    throw Error(ErrorKind::Usage,
                source + ": no loop to select near a point (the mesh has no boundary)");
  }
  int best = 0;
  double best_distance = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < loops.size(); ++i) {
    const double d = distance_to_loop(point, loops[i], source);
    if (d < best_distance) {
      best_distance = d;
      best = static_cast<int>(i);
    }
  }
  return best;
}

std::string not_a_disk(const BoundaryLoop& loop) {
  return "loop " + std::to_string(loop.id) + " is not a disk boundary (" + loop.reason + ")";
}

// The loops named explicitly (ids or near): all must exist and be disks.
std::vector<int> named_loops(const std::vector<BoundaryLoop>& loops, const HoleSelection& selection,
                             const std::string& source) {
  std::vector<int> ids = selection.ids;
  if (selection.mode == HoleSelection::Mode::Near) {
    ids = {nearest_loop(loops, selection.near, source)};
  }
  for (int id : ids) {
    if (id < 0 || id >= static_cast<int>(loops.size())) {
      throw Error(ErrorKind::Usage, source + ": no loop with id " + std::to_string(id) +
                                        " (the mesh has " + std::to_string(loops.size()) +
                                        " loops)");
    }
    if (!loops[id].is_disk) throw Error(ErrorKind::NotADisk, source + ": " + not_a_disk(loops[id]));
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  return ids;
}

}  // namespace

std::vector<BoundaryLoop> find_boundary_loops(const Mesh& mesh, const std::string& source) {
  const EdgeTopology topology = build_edge_topology(mesh.faces, mesh.vertex_count(), source);
  CornerFans fans = group_corners_into_fans(mesh.faces, topology);
  const std::vector<char> pinched =
      find_pinched_vertices(mesh.faces, topology, fans, mesh.vertex_count(), source);
  const std::vector<BoundaryHalfEdge> half_edges = boundary_half_edges(topology);
  const std::vector<int> next = link_boundary_half_edges(mesh.faces, half_edges, fans, source);

  std::vector<std::vector<int>> cycles = trace_cycles(half_edges, next, source);
  std::vector<BoundaryLoop> loops;
  loops.reserve(cycles.size());
  for (auto& cycle : cycles) {
    loops.push_back(make_loop(static_cast<int>(loops.size()), std::move(cycle), mesh.positions));
  }
  flag_pinched_loops(loops, pinched);
  measure_turning(mesh, loops);
  return loops;
}

std::vector<int> default_outer_loops(const std::vector<BoundaryLoop>& loops, int keep_open) {
  std::vector<int> order(loops.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return loops[a].length > loops[b].length; });
  order.resize(std::min(order.size(), static_cast<size_t>(std::max(keep_open, 0))));
  std::sort(order.begin(), order.end());
  return order;
}

bool turns_like_a_hole(const BoundaryLoop& loop) { return loop.turning > M_PI; }

HoleChoice select_holes(const std::vector<BoundaryLoop>& loops, const HoleSelection& selection,
                        const std::string& source) {
  using Mode = HoleSelection::Mode;
  std::vector<char> to_fill(loops.size(), 0);
  HoleChoice choice;
  if (selection.mode == Mode::Ids || selection.mode == Mode::Near) {
    for (int id : named_loops(loops, selection, source)) to_fill[id] = 1;
  } else {
    std::vector<char> outer(loops.size(), 0);
    if (selection.mode == Mode::Default) {
      for (int id : default_outer_loops(loops, selection.keep_open)) outer[id] = 1;
    }
    if (selection.mode == Mode::Auto) {
      for (size_t id = 0; id < loops.size(); ++id) outer[id] = !turns_like_a_hole(loops[id]);
    }
    for (size_t id = 0; id < loops.size(); ++id) {
      if (outer[id]) continue;
      if (loops[id].is_disk) {
        to_fill[id] = 1;
      } else {
        choice.warnings.push_back(not_a_disk(loops[id]) + ": left open");
      }
    }
  }
  for (size_t id = 0; id < loops.size(); ++id) {
    (to_fill[id] ? choice.fill : choice.left_open).push_back(static_cast<int>(id));
  }
  return choice;
}

}  // namespace foldfill
