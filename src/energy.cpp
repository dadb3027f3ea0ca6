// The fabric energy of Gisbert et al. 2023, sections 3.3-3.4, over the glued
// flat strip + patch domain. Everything that depends only on the rest state is
// precomputed in the constructor; evaluate() works on flat arrays.
#include "foldfill/energy.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

#include "foldfill/error.h"
#include "foldfill/topology.h"

namespace foldfill {
namespace {

using Spring = FabricEnergy::Spring;
using Points = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

double rest_distance(const std::vector<Vec2>& uv, int i, int j) {
  return std::hypot(uv[i][0] - uv[j][0], uv[i][1] - uv[j][1]);
}

// Twice the signed area of the flat triangle (a, b, c).
double double_area(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

// Cotangent of the flat angle at `a` in the triangle (a, b, c).
double cotangent_at(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double dot = (b[0] - a[0]) * (c[0] - a[0]) + (b[1] - a[1]) * (c[1] - a[1]);
  return dot / std::abs(double_area(a, b, c));
}

void check_domain(const EmbedDomain& domain) {
  const int n = domain.vertex_count();
  if (domain.fixed_count < 0 || domain.fixed_count > n ||
      static_cast<int>(domain.fixed_positions.size()) != domain.fixed_count) {
    throw Error(ErrorKind::Internal, "energy: fixed_positions does not match fixed_count");
  }
  for (size_t f = 0; f < domain.faces.size(); ++f) {
    const Tri& t = domain.faces[f];
    for (int v : t) {
      if (v < 0 || v >= n) {
        throw Error(ErrorKind::Internal, "energy: face " + std::to_string(f) + " out of range");
      }
    }
    // Cotangents and areas below need proper counter-clockwise rest triangles.
    if (!(double_area(domain.rest_uv[t[0]], domain.rest_uv[t[1]], domain.rest_uv[t[2]]) > 0)) {
      throw Error(ErrorKind::FillFailed,
                  "energy: rest triangle " + std::to_string(f) + " is degenerate or clockwise");
    }
  }
}

void check_options(const EnergyOptions& options) {
  const auto valid = [](double w) { return std::isfinite(w) && w >= 0; };
  if (!valid(options.lambda) || !valid(options.repulsion) || !valid(options.repulsion_radius)) {
    throw Error(ErrorKind::Usage,
                "energy options: lambda, repulsion and repulsion_radius must be finite and >= 0");
  }
}

// Read access to the CSR vertex adjacency.
struct VertexGraph {
  const std::vector<int>& start;
  const std::vector<int>& neighbours;
  bool adjacent(int i, int j) const {
    return std::binary_search(neighbours.begin() + start[i], neighbours.begin() + start[i + 1], j);
  }
};

// Sorted neighbour lists of every vertex, in CSR form.
void build_adjacency(const EdgeTopology& topology, int vertex_count, std::vector<int>& start,
                     std::vector<int>& neighbours) {
  start.assign(vertex_count + 1, 0);
  for (const Edge& e : topology.edges) {
    ++start[e.v0 + 1];
    ++start[e.v1 + 1];
  }
  for (int v = 0; v < vertex_count; ++v) start[v + 1] += start[v];
  neighbours.resize(start[vertex_count]);
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (const Edge& e : topology.edges) {
    neighbours[fill[e.v0]++] = e.v1;
    neighbours[fill[e.v1]++] = e.v0;
  }
  for (int v = 0; v < vertex_count; ++v) {
    std::sort(neighbours.begin() + start[v], neighbours.begin() + start[v + 1]);
  }
}

std::vector<Spring> edge_springs(const EmbedDomain& domain, const EdgeTopology& topology) {
  std::vector<Spring> springs;
  for (const Edge& e : topology.edges) {
    if (e.v1 >= domain.fixed_count) {  // v0 < v1: v1 is the later, possibly free, end
      springs.push_back({e.v0, e.v1, rest_distance(domain.rest_uv, e.v0, e.v1)});
    }
  }
  return springs;
}

// Springs to the vertices at graph distance exactly 2 (the prototype's
// "2-Ring" bending), each pair once (i < j), with at least one free end.
std::vector<Spring> two_ring_springs(const EmbedDomain& domain, const VertexGraph& graph) {
  std::vector<Spring> springs;
  std::vector<int> ring;
  for (int i = 0; i < domain.vertex_count(); ++i) {
    ring.clear();
    for (int a = graph.start[i]; a < graph.start[i + 1]; ++a) {
      const int k = graph.neighbours[a];
      for (int b = graph.start[k]; b < graph.start[k + 1]; ++b) {
        const int j = graph.neighbours[b];
        if (j > i && j >= domain.fixed_count && !graph.adjacent(i, j)) ring.push_back(j);
      }
    }
    std::sort(ring.begin(), ring.end());
    ring.erase(std::unique(ring.begin(), ring.end()), ring.end());
    for (int j : ring) springs.push_back({i, j, rest_distance(domain.rest_uv, i, j)});
  }
  return springs;
}

// Bergou et al. 2006: per interior edge (x0, x1) with triangles (x0, x1, x2)
// and (x0, x1, x3), Q = 3 / (A0 + A1) K K^T, assembled per coordinate.
Eigen::SparseMatrix<double> quadratic_bending_hessian(const EmbedDomain& domain,
                                                      const EdgeTopology& topology) {
  const auto& uv = domain.rest_uv;
  std::vector<Eigen::Triplet<double>> entries;
  for (const Edge& e : topology.edges) {
    if (e.is_boundary()) continue;
    const int x[4] = {e.v0, e.v1, e.opposite[0], e.opposite[1]};
    if (std::max({x[0], x[1], x[2], x[3]}) < domain.fixed_count) continue;  // constant term
    const Vec2 &p0 = uv[x[0]], &p1 = uv[x[1]], &p2 = uv[x[2]], &p3 = uv[x[3]];
    const double c01 = cotangent_at(p0, p1, p2), c02 = cotangent_at(p0, p1, p3);
    const double c03 = cotangent_at(p1, p0, p2), c04 = cotangent_at(p1, p0, p3);
    const double areas =
        0.5 * (std::abs(double_area(p0, p1, p2)) + std::abs(double_area(p0, p1, p3)));
    const double k[4] = {c03 + c04, c01 + c02, -c01 - c03, -c02 - c04};
    const double scale = 3 / areas;
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) entries.emplace_back(x[a], x[b], scale * k[a] * k[b]);
    }
  }
  const int n = domain.vertex_count();
  Eigen::SparseMatrix<double> hessian(n, n);
  hessian.setFromTriplets(entries.begin(), entries.end());
  return hessian;
}

// r_i = factor * the shortest rest edge at vertex i (0 for an isolated vertex).
std::vector<double> repulsion_radii(const EmbedDomain& domain, const EdgeTopology& topology,
                                    double factor) {
  std::vector<double> shortest(domain.vertex_count(), HUGE_VAL);
  for (const Edge& e : topology.edges) {
    const double l = rest_distance(domain.rest_uv, e.v0, e.v1);
    shortest[e.v0] = std::min(shortest[e.v0], l);
    shortest[e.v1] = std::min(shortest[e.v1], l);
  }
  std::vector<double> radius(shortest.size());
  for (size_t v = 0; v < shortest.size(); ++v) {
    radius[v] = shortest[v] == HUGE_VAL ? 0 : factor * shortest[v];
  }
  return radius;
}

// 1/2 sum (|x_i - x_j| - l)^2; adds `weight` times its gradient to `forces`
// when non-null. Shared by the isometric and the two-ring bending terms.
double spring_energy(const std::vector<Spring>& springs, const Points& points, double weight,
                     Points* forces) {
  double energy = 0;
  for (const Spring& s : springs) {
    const double d[3] = {points(s.i, 0) - points(s.j, 0), points(s.i, 1) - points(s.j, 1),
                         points(s.i, 2) - points(s.j, 2)};
    const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const double stretch = length - s.rest_length;
    energy += stretch * stretch;
    if (forces && length > 0) {
      const double f = weight * stretch / length;
      for (int c = 0; c < 3; ++c) {
        (*forces)(s.i, c) += f * d[c];
        (*forces)(s.j, c) -= f * d[c];
      }
    }
  }
  return 0.5 * energy;
}

// A uniform grid over the points for fixed-radius neighbour queries. Cells
// are twice the query radius, so the ball around a point meets at most 2 cells
// per axis, its own and the neighbour on the nearer side: 8 in all. Occupied
// cells live in an open-addressing hash table; the points are regrouped by
// cell (in increasing index order within a cell) so that a cell's candidates
// are contiguous and queries are deterministic.
class SpatialGrid {
 public:
  SpatialGrid(const Points& points, double query_radius)
      : points_(points), inverse_cell_(0.5 / query_radius) {
    const int n = static_cast<int>(points.rows());
    int bits = 1;
    while ((size_t{1} << bits) < 2 * static_cast<size_t>(n)) ++bits;  // load <= 1/2
    shift_ = 64 - bits;
    slots_.assign(size_t{1} << bits, Slot{});
    std::vector<int> slot_of(n);
    for (int v = 0; v < n; ++v) {
      int64_t cell[3];
      bool upper[3];
      locate(v, cell, upper);
      slot_of[v] = find_or_insert(pack(cell[0], cell[1], cell[2]));
      ++slots_[slot_of[v]].count;
    }
    int end = 0;  // slots get their range's end, then count down to its start
    for (Slot& slot : slots_) slot.start = end += slot.count;
    vertex_.resize(n);
    position_.resize(3 * static_cast<size_t>(n));
    for (int v = n - 1; v >= 0; --v) {
      const int k = --slots_[slot_of[v]].start;
      vertex_[k] = v;
      for (int a = 0; a < 3; ++a) position_[3 * static_cast<size_t>(k) + a] = points(v, a);
    }
  }

  // Calls visit(j, position of j) for every vertex j that may lie within the
  // query radius of vertex i (i itself included), each once, in a fixed order.
  template <typename Visit>
  void for_each_near(int i, Visit&& visit) const {
    int64_t cell[3];
    bool upper[3];
    locate(i, cell, upper);
    for (int corner = 0; corner < 8; ++corner) {
      int64_t c[3];
      for (int a = 0; a < 3; ++a) c[a] = cell[a] + ((corner >> a) & 1 ? (upper[a] ? 1 : -1) : 0);
      const Slot* slot = find(pack(c[0], c[1], c[2]));
      if (!slot) continue;
      for (int k = slot->start; k < slot->start + slot->count; ++k) {
        visit(vertex_[k], &position_[3 * static_cast<size_t>(k)]);
      }
    }
  }

 private:
  struct Slot {
    uint64_t key = 0;  // packed cell
    int start = 0;     // first of the cell's points in vertex_ / position_
    int count = 0;     // 0: empty slot
  };

  // The cell of vertex v and, per axis, whether v is in the cell's upper half.
  void locate(int v, int64_t cell[3], bool upper[3]) const {
    for (int a = 0; a < 3; ++a) {
      const double scaled = points_(v, a) * inverse_cell_;
      // Clamped (NaN included) so that far or non-finite points cannot
      // overflow the cast; their cells merely coincide with others.
      const double limit = 4e15;
      const double floor = scaled > -limit && scaled < limit ? std::floor(scaled) : 0;
      cell[a] = static_cast<int64_t>(floor);
      upper[a] = scaled - floor >= 0.5;
    }
  }
  // 21 bits per axis: cells 2^21 apart share a key, which only adds candidates.
  static uint64_t pack(int64_t x, int64_t y, int64_t z) {
    const uint64_t mask = (uint64_t{1} << 21) - 1;
    return (static_cast<uint64_t>(x) & mask) | (static_cast<uint64_t>(y) & mask) << 21 |
           (static_cast<uint64_t>(z) & mask) << 42;
  }
  size_t home(uint64_t key) const { return (key * 0x9E3779B97F4A7C15ULL) >> shift_; }
  size_t next(size_t s) const { return (s + 1) & (slots_.size() - 1); }

  int find_or_insert(uint64_t key) {
    size_t s = home(key);
    while (slots_[s].count > 0 && slots_[s].key != key) s = next(s);
    slots_[s].key = key;
    return static_cast<int>(s);
  }
  const Slot* find(uint64_t key) const {
    for (size_t s = home(key); slots_[s].count > 0; s = next(s)) {
      if (slots_[s].key == key) return &slots_[s];
    }
    return nullptr;
  }

  const Points& points_;
  double inverse_cell_;
  int shift_ = 63;
  std::vector<Slot> slots_;
  std::vector<int> vertex_;       // grouped by cell
  std::vector<double> position_;  // xyz of vertex_, for contiguous candidate scans
};

// 1/2 sum over pairs (i < j, at least one free, not joined by an edge) of
// max(r_ij - |x_i - x_j|, 0)^2 with the symmetric pair radius r_ij = (r_i +
// r_j) / 2; adds `weight` times its gradient to `forces` when non-null. Pairs
// are visited by their later vertex, then by grid cell and the earlier vertex,
// so the sum is reproducible.
double repulsion_energy(const Points& points, const std::vector<double>& radius, int fixed_count,
                        const VertexGraph& graph, double weight, Points* forces) {
  if (radius.empty()) return 0;
  const double max_radius = *std::max_element(radius.begin(), radius.end());
  if (!(max_radius > 0)) return 0;
  const SpatialGrid grid(points, max_radius);  // r_ij <= max_radius
  double energy = 0;
  // Each pair once: from its later vertex i, which is free (fixed ones come first).
  for (int i = fixed_count; i < static_cast<int>(points.rows()); ++i) {
    const double pi[3] = {points(i, 0), points(i, 1), points(i, 2)};
    grid.for_each_near(i, [&](int j, const double* pj) {
      const double d[3] = {pi[0] - pj[0], pi[1] - pj[1], pi[2] - pj[2]};
      const double distance_sq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
      const double r = 0.5 * (radius[i] + radius[j]);
      const bool close = (j < i) & (distance_sq < r * r);  // one, rarely taken, branch
      if (!close || graph.adjacent(i, j)) return;
      const double distance = std::sqrt(distance_sq), overlap = r - distance;
      energy += overlap * overlap;
      if (forces && distance > 0) {
        const double f = -weight * overlap / distance;
        for (int c = 0; c < 3; ++c) {
          (*forces)(i, c) += f * d[c];
          (*forces)(j, c) -= f * d[c];
        }
      }
    });
  }
  return 0.5 * energy;
}

}  // namespace

FabricEnergy::FabricEnergy(const EmbedDomain& domain, const EnergyOptions& options)
    : domain_(domain), options_(options) {
  check_domain(domain_);
  check_options(options_);
  const int n = domain_.vertex_count();
  const EdgeTopology topology = build_edge_topology(domain_.faces, n, "energy domain");
  build_adjacency(topology, n, neighbour_start_, neighbours_);
  springs_ = edge_springs(domain_, topology);
  if (options_.bending == BendingModel::Quadratic) {
    bending_hessian_ = quadratic_bending_hessian(domain_, topology);
  } else {
    two_ring_springs_ = two_ring_springs(domain_, VertexGraph{neighbour_start_, neighbours_});
  }
  repulsion_radius_ = repulsion_radii(domain_, topology, options_.repulsion_radius);
  points_.setZero(n, 3);
  for (int v = 0; v < domain_.fixed_count; ++v) {
    for (int c = 0; c < 3; ++c) points_(v, c) = domain_.fixed_positions[v][c];
  }
  forces_.setZero(n, 3);
}

EnergyTerms FabricEnergy::evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* gradient) const {
  const int free = domain_.free_count();
  if (x.size() != 3 * static_cast<Eigen::Index>(free)) {
    throw Error(ErrorKind::Internal, "energy: expected " + std::to_string(3 * free) +
                                         " variables, got " + std::to_string(x.size()));
  }
  points_.bottomRows(free) = Eigen::Map<const Points>(x.data(), free, 3);
  Points* forces = gradient ? &forces_ : nullptr;

  EnergyTerms terms;
  if (options_.bending == BendingModel::Quadratic) {
    // E_B = 1/2 sum over coordinates p^T H p; its gradient is H p.
    forces_.noalias() = bending_hessian_ * points_;
    terms.bending = 0.5 * points_.cwiseProduct(forces_).sum();
    if (forces) forces_ *= options_.lambda;
  } else {
    forces_.setZero();
    terms.bending = spring_energy(two_ring_springs_, points_, options_.lambda, forces);
  }
  terms.isometric = spring_energy(springs_, points_, 1, forces);
  if (options_.repulsion > 0) {  // skipped (reported 0) when switched off: it is the costly term
    terms.repulsion =
        repulsion_energy(points_, repulsion_radius_, domain_.fixed_count,
                         VertexGraph{neighbour_start_, neighbours_}, options_.repulsion, forces);
  }
  terms.total =
      terms.isometric + options_.lambda * terms.bending + options_.repulsion * terms.repulsion;

  if (gradient) {
    gradient->resize(3 * static_cast<Eigen::Index>(free));
    Eigen::Map<Points>(gradient->data(), free, 3) = forces_.bottomRows(free);
  }
  return terms;
}

std::vector<Vec3> FabricEnergy::positions(const Eigen::VectorXd& x) const {
  const int free = domain_.free_count();
  if (x.size() != 3 * static_cast<Eigen::Index>(free)) {
    throw Error(ErrorKind::Internal, "energy: wrong number of variables");
  }
  std::vector<Vec3> result(domain_.fixed_positions);
  result.reserve(domain_.vertex_count());
  for (int v = 0; v < free; ++v) result.push_back({x[3 * v], x[3 * v + 1], x[3 * v + 2]});
  return result;
}

Eigen::VectorXd FabricEnergy::variables(const std::vector<Vec3>& positions) const {
  if (static_cast<int>(positions.size()) != domain_.vertex_count()) {
    throw Error(ErrorKind::Internal, "energy: wrong number of positions");
  }
  const int fixed = domain_.fixed_count, free = domain_.free_count();
  Eigen::VectorXd x(3 * static_cast<Eigen::Index>(free));
  for (int v = 0; v < free; ++v) {
    for (int c = 0; c < 3; ++c) x[3 * v + c] = positions[fixed + v][c];
  }
  return x;
}

}  // namespace foldfill
