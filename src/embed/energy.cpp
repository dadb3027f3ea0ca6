// The fabric energy of Gisbert et al. 2023, sections 3.3-3.4, over the glued
// flat strip + patch domain. Everything that depends only on the rest state is
// precomputed in the constructor; evaluate() works on flat arrays.
#include "foldfill/energy.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

#include "foldfill/box_tree.h"
#include "foldfill/error.h"
#include "foldfill/topology.h"

namespace foldfill {
namespace {

using Spring = FabricEnergy::Spring;
using Points = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

// The skin of the repulsion's candidate list, relative to the largest radius
// of a patch vertex: a wider skin lets the list last more iterations but
// makes it longer.
constexpr double kRepulsionSkin = 0.5;

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
    throw InternalError("energy: fixed_positions does not match fixed_count");
  }
  for (size_t f = 0; f < domain.faces.size(); ++f) {
    const Tri& t = domain.faces[f];
    for (int v : t) {
      if (v < 0 || v >= n) {
        throw InternalError("energy: face " + std::to_string(f) + " out of range");
      }
    }
    // Cotangents and areas below need proper counter-clockwise rest triangles.
    if (!(double_area(domain.rest_uv[t[0]], domain.rest_uv[t[1]], domain.rest_uv[t[2]]) > 0)) {
      throw FillFailedError("energy: rest triangle " + std::to_string(f) +
                            " is degenerate or clockwise");
    }
  }
}

void check_options(const EnergyOptions& options) {
  const auto valid = [](double w) { return std::isfinite(w) && w >= 0; };
  if (!valid(options.lambda) || !valid(options.repulsion) || !valid(options.repulsion_radius)) {
    throw UsageError(
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
std::vector<Spring> find_two_ring_springs(const EmbedDomain& domain, const VertexGraph& graph) {
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
  // Raw rows: Eigen's indexing recomputed every address.
  const double* position = points.data();
  double* force = forces ? forces->data() : nullptr;
  double energy = 0;
  for (const Spring& s : springs) {
    const double* pi = position + 3 * static_cast<ptrdiff_t>(s.i);
    const double* pj = position + 3 * static_cast<ptrdiff_t>(s.j);
    const double d[3] = {pi[0] - pj[0], pi[1] - pj[1], pi[2] - pj[2]};
    const double length = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    const double stretch = length - s.rest_length;
    energy += stretch * stretch;
    if (force && length > 0) {
      const double f = weight * stretch / length;
      double* fi = force + 3 * static_cast<ptrdiff_t>(s.i);
      double* fj = force + 3 * static_cast<ptrdiff_t>(s.j);
      for (int c = 0; c < 3; ++c) {
        fi[c] += f * d[c];
        fj[c] -= f * d[c];
      }
    }
  }
  return 0.5 * energy;
}

// The quadratic bending energy 1/2 sum over coordinates p^T H p from the free
// rows of H (see FabricEnergy::split_bending_hessian): H_ff, b = H_fx p_x
// (`fixed_force`) and c = p_x^T H_xx p_x (`fixed_energy`). Sets the free rows
// of `forces` to `weight` times the gradient H_ff p_f + b when non-null. One
// pass over H_ff for the three coordinates (Eigen's sparse-dense product
// makes one per coordinate), each row summed in Eigen's order, so that the
// gradient is the same bit for bit.
double quadratic_bending_energy(const Eigen::SparseMatrix<double, Eigen::RowMajor>& free_hessian,
                                const Points& fixed_force, double fixed_energy,
                                const Points& points, double weight, Points* forces) {
  const Eigen::Index free = free_hessian.rows(), fixed = points.rows() - free;
  const int* row_start = free_hessian.outerIndexPtr();
  const int* column = free_hessian.innerIndexPtr();
  const double* value = free_hessian.valuePtr();
  const double* free_points = points.data() + 3 * fixed;
  const double* constant_force = fixed_force.data();
  double* free_forces = forces ? forces->data() + 3 * fixed : nullptr;
  double sum = 0;
  for (Eigen::Index row = 0; row < free; ++row) {
    double hp[3] = {0, 0, 0};
    for (int k = row_start[row]; k < row_start[row + 1]; ++k) {
      const double* q = free_points + 3 * static_cast<Eigen::Index>(column[k]);
      for (int c = 0; c < 3; ++c) hp[c] += value[k] * q[c];
    }
    for (int c = 0; c < 3; ++c) {
      const Eigen::Index at = 3 * row + c;
      const double force = hp[c] + constant_force[at];
      sum += free_points[at] * (force + constant_force[at]);
      if (free_forces) free_forces[at] = weight * force;
    }
  }
  return 0.5 * (sum + fixed_energy);
}

using RepulsionPair = FabricEnergy::RepulsionPair;

// The box of vertex v for the repulsion's pair search: around it by half its
// radius plus half the skin (a little more, for rounding), so that the boxes
// of a pair that reaches r_ij + skin meet. A non-finite position makes an
// empty box, which meets nothing.
Box repulsion_box(const Points& points, const std::vector<double>& radius, double skin, int v) {
  const double reach = (0.5 * radius[v] + 0.5 * skin) * (1 + 1e-6) + 1e-9;
  Box box;
  for (int c = 0; c < 3; ++c) {
    box.low[c] = points(v, c) - reach;
    box.high[c] = points(v, c) + reach;
  }
  return box;
}

// A refitted tree whose search cost grew past this factor of its cost when
// built is built again (the vertices moved far from where they were).
constexpr double kRepulsionRebuildFactor = 2;

}  // namespace

// The candidate pairs of the repulsion (a "Verlet list"): every pair (i > j,
// i free, not joined by an edge) closer than its radius r_ij = (r_i + r_j) / 2
// plus the skin at the current positions, sorted by (i, j). While no two
// vertices can have come closer by more than the skin since the build
// (closing_bound), every pair closer than its radius is in the list, so
// summing over the list is summing over all pairs; the order makes the sum
// independent of when the list was built (and of how the pairs were found).
//
// The pairs are found by the shared box tree (repulsion_box): the free
// vertices against each other, and against the fixed ones, whose tree is
// built once; two fixed vertices never repel. The free vertices' tree is
// refitted from search to search, and built again when it has grown slow.
void FabricEnergy::build_repulsion_pairs() const {
  const int n = static_cast<int>(points_.rows()), fixed_count = domain_.fixed_count;
  const double skin = repulsion_skin_;
  if (repulsion_fixed_tree_.box_count() != fixed_count) {
    std::vector<Box> fixed_boxes(fixed_count);
    for (int v = 0; v < fixed_count; ++v)
      fixed_boxes[v] = repulsion_box(points_, repulsion_radius_, skin, v);
    repulsion_fixed_tree_.build(fixed_boxes);
  }
  std::vector<Box> free_boxes(n - fixed_count);
  for (int v = fixed_count; v < n; ++v)
    free_boxes[v - fixed_count] = repulsion_box(points_, repulsion_radius_, skin, v);
  const bool refit = repulsion_free_tree_.box_count() == n - fixed_count;
  if (refit) repulsion_free_tree_.refit(free_boxes);
  if (!refit || repulsion_free_tree_.cost() > kRepulsionRebuildFactor * repulsion_free_tree_cost_) {
    repulsion_free_tree_.build(free_boxes);
    repulsion_free_tree_cost_ = repulsion_free_tree_.cost();
  }

  const VertexGraph graph{neighbour_start_, neighbours_};
  std::vector<RepulsionPair> found;
  const auto consider = [&](int a, int b) {
    const double d[3] = {points_(a, 0) - points_(b, 0), points_(a, 1) - points_(b, 1),
                         points_(a, 2) - points_(b, 2)};
    const double r = 0.5 * (repulsion_radius_[a] + repulsion_radius_[b]);
    if (!(d[0] * d[0] + d[1] * d[1] + d[2] * d[2] < (r + skin) * (r + skin))) return;
    const int i = std::max(a, b), j = std::min(a, b);
    if (!graph.adjacent(i, j)) found.push_back({i, j, r});
  };
  repulsion_free_tree_.for_each_meeting_pair(
      0.0, [&](int a, int b) { consider(fixed_count + a, fixed_count + b); });
  repulsion_free_tree_.for_each_meeting_pair(repulsion_fixed_tree_, 0.0,
                                             [&](int a, int b) { consider(fixed_count + a, b); });
  // Counting sort by i, then each i's few pairs by j.
  std::vector<int> start(n + 1, 0);
  for (const RepulsionPair& pair : found) ++start[pair.i + 1];
  for (int v = 0; v < n; ++v) start[v + 1] += start[v];
  repulsion_pairs_.resize(found.size());
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (const RepulsionPair& pair : found) repulsion_pairs_[fill[pair.i]++] = pair;
  for (int v = fixed_count; v < n; ++v) {
    std::sort(repulsion_pairs_.begin() + start[v], repulsion_pairs_.begin() + start[v + 1],
              [](const RepulsionPair& p, const RepulsionPair& q) { return p.j < q.j; });
  }
}

namespace {

// 1/2 sum over the close pairs of max(r_ij - |x_i - x_j|, 0)^2; adds `weight`
// times its gradient to `forces` when non-null.
double repulsion_energy(const Points& points, const std::vector<RepulsionPair>& pairs,
                        double weight, Points* forces) {
  double energy = 0;
  for (const RepulsionPair& pair : pairs) {
    const double d[3] = {points(pair.i, 0) - points(pair.j, 0),
                         points(pair.i, 1) - points(pair.j, 1),
                         points(pair.i, 2) - points(pair.j, 2)};
    const double distance_sq = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
    if (!(distance_sq < pair.radius * pair.radius)) continue;
    const double distance = std::sqrt(distance_sq), overlap = pair.radius - distance;
    energy += overlap * overlap;
    if (forces && distance > 0) {
      const double f = -weight * overlap / distance;
      for (int c = 0; c < 3; ++c) {
        (*forces)(pair.i, c) += f * d[c];
        (*forces)(pair.j, c) -= f * d[c];
      }
    }
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
    two_ring_springs_ = find_two_ring_springs(domain_, VertexGraph{neighbour_start_, neighbours_});
  }
  repulsion_radius_ = repulsion_radii(domain_, topology, options_.repulsion_radius);
  // The skin scales with the patch's radii (long strip edges give a few larger ones).
  const auto largest = [&](int first) {
    return first < n ? *std::max_element(repulsion_radius_.begin() + first, repulsion_radius_.end())
                     : 0.0;
  };
  const double patch_radius = largest(domain_.fixed_count);
  repulsion_skin_ = kRepulsionSkin * (patch_radius > 0 ? patch_radius : largest(0));
  points_.setZero(n, 3);
  for (int v = 0; v < domain_.fixed_count; ++v) {
    for (int c = 0; c < 3; ++c) points_(v, c) = domain_.fixed_positions[v][c];
  }
  forces_.setZero(n, 3);
  if (options_.bending == BendingModel::Quadratic) split_bending_hessian();
}

// With p = (p_x fixed, p_f free), p^T H p = p_f^T (H_ff p_f + 2 b) + c where
// b = H_fx p_x and c = p_x^T H_xx p_x are constant: only the free rows of H
// take part in an evaluation.
void FabricEnergy::split_bending_hessian() {
  const int fixed = domain_.fixed_count, free = domain_.free_count();
  const Points fixed_points = points_.topRows(fixed);
  free_bending_hessian_ = bending_hessian_.bottomRightCorner(free, free);
  free_bending_hessian_.makeCompressed();  // quadratic_bending_energy reads its arrays
  fixed_bending_force_ = bending_hessian_.bottomLeftCorner(free, fixed) * fixed_points;
  fixed_bending_energy_ =
      fixed_points.cwiseProduct(bending_hessian_.topLeftCorner(fixed, fixed) * fixed_points).sum();
}

EnergyTerms FabricEnergy::evaluate(const Eigen::VectorXd& x, Eigen::VectorXd* gradient) const {
  const int free = domain_.free_count();
  if (x.size() != 3 * static_cast<Eigen::Index>(free)) {
    throw InternalError("energy: expected " + std::to_string(3 * free) + " variables, got " +
                        std::to_string(x.size()));
  }
  points_.bottomRows(free) = Eigen::Map<const Points>(x.data(), free, 3);
  Points* forces = gradient ? &forces_ : nullptr;

  EnergyTerms terms;
  forces_.topRows(domain_.fixed_count).setZero();  // springs add to them; never read
  if (options_.bending == BendingModel::Quadratic) {
    terms.bending =
        quadratic_bending_energy(free_bending_hessian_, fixed_bending_force_, fixed_bending_energy_,
                                 points_, options_.lambda, forces);
  } else {
    if (forces) forces_.bottomRows(free).setZero();
    terms.bending = spring_energy(two_ring_springs_, points_, options_.lambda, forces);
  }
  terms.isometric = spring_energy(springs_, points_, 1, forces);
  if (options_.repulsion > 0 && repulsion_skin_ > 0) {
    update_repulsion_pairs();
    terms.repulsion = repulsion_energy(points_, repulsion_pairs_, options_.repulsion, forces);
  }
  terms.total =
      terms.isometric + options_.lambda * terms.bending + options_.repulsion * terms.repulsion;

  if (gradient) {
    gradient->resize(3 * static_cast<Eigen::Index>(free));
    Eigen::Map<Points>(gradient->data(), free, 3) = forces_.bottomRows(free);
  }
  return terms;
}

// Rebuilt only when two vertices may have come closer by the skin since the
// last build (closing_bound): late iterations move little, so most
// evaluations reuse the list.
void FabricEnergy::update_repulsion_pairs() const {
  if (repulsion_anchor_.rows() == points_.rows() &&
      closing_bound(points_.data(), repulsion_anchor_.data(),
                    static_cast<size_t>(domain_.fixed_count),
                    static_cast<size_t>(points_.rows())) <= repulsion_skin_) {
    return;
  }
  build_repulsion_pairs();
  repulsion_anchor_ = points_;
}

namespace {

// Adds weight * the Laplacian of `springs` over the free vertices to `entries`.
void add_spring_laplacian(const std::vector<Spring>& springs, int fixed, double weight,
                          std::vector<Eigen::Triplet<double>>& entries) {
  for (const Spring& s : springs) {
    const int i = s.i - fixed, j = s.j - fixed;
    if (i >= 0) entries.emplace_back(i, i, weight);
    if (j >= 0) entries.emplace_back(j, j, weight);
    if (i >= 0 && j >= 0) {
      entries.emplace_back(i, j, -weight);
      entries.emplace_back(j, i, -weight);
    }
  }
}

// Adds weight * the free block of `hessian` (over all domain vertices, the
// first `fixed` of them fixed) to `entries`.
void add_free_block(const Eigen::SparseMatrix<double>& hessian, int fixed, double weight,
                    std::vector<Eigen::Triplet<double>>& entries) {
  for (int col = fixed; col < hessian.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(hessian, col); it; ++it)
      if (it.row() >= fixed)
        entries.emplace_back(static_cast<int>(it.row()) - fixed, col - fixed, weight * it.value());
}

double diagonal_sum(const std::vector<Eigen::Triplet<double>>& entries) {
  double sum = 0;
  for (const Eigen::Triplet<double>& entry : entries)
    if (entry.row() == entry.col()) sum += entry.value();
  return sum;
}

// The bending part makes the factor denser (a two-ring stencil), so it is
// left out where it buys too little: where it weighs under this share of the
// springs' diagonal (at the default lambda), and on the quadratic model's
// patches above this many free vertices, where the dearer solves outweigh the
// iterations it saves (docs/benchmarks.md).
constexpr double kSmallestBendingShare = 0.01;
constexpr int kLargestBendingPreconditioner = 40000;

}  // namespace

Eigen::SparseMatrix<double> FabricEnergy::preconditioner() const {
  const int fixed = domain_.fixed_count;
  const int free_count = domain_.free_count();
  const double lambda = options_.lambda;
  std::vector<Eigen::Triplet<double>> entries, bending;
  add_spring_laplacian(springs_, fixed, 1.0, entries);
  add_spring_laplacian(two_ring_springs_, fixed, lambda, bending);
  if (free_count <= kLargestBendingPreconditioner)
    add_free_block(bending_hessian_, fixed, lambda, bending);
  if (diagonal_sum(bending) >= kSmallestBendingShare * diagonal_sum(entries))
    entries.insert(entries.end(), bending.begin(), bending.end());
  Eigen::SparseMatrix<double> p(free_count, free_count);
  p.setFromTriplets(entries.begin(), entries.end());
  return p;
}

std::vector<Vec3> FabricEnergy::positions(const Eigen::VectorXd& x) const {
  const int free = domain_.free_count();
  if (x.size() != 3 * static_cast<Eigen::Index>(free)) {
    throw InternalError("energy: wrong number of variables");
  }
  std::vector<Vec3> result(domain_.fixed_positions);
  result.reserve(domain_.vertex_count());
  for (int v = 0; v < free; ++v) result.push_back({x[3 * v], x[3 * v + 1], x[3 * v + 2]});
  return result;
}

Eigen::VectorXd FabricEnergy::variables(const std::vector<Vec3>& positions) const {
  if (static_cast<int>(positions.size()) != domain_.vertex_count()) {
    throw InternalError("energy: wrong number of positions");
  }
  const int fixed = domain_.fixed_count, free = domain_.free_count();
  Eigen::VectorXd x(3 * static_cast<Eigen::Index>(free));
  for (int v = 0; v < free; ++v) {
    for (int c = 0; c < 3; ++c) x[3 * v + c] = positions[fixed + v][c];
  }
  return x;
}

}  // namespace foldfill
