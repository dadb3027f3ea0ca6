// As-rigid-as-possible embedding (Sorkine & Alexa 2007) of the domain with a
// shrunk rest shape, the initialisation of section 3.3 of Gisbert et al. 2023.
//
// Energy: sum_i sum_{j in N(i)} w_ij |(x_i - x_j) - R_i (p_i - p_j)|^2 with p
// the rest shape (flat uv scaled by c, z = 0) and w_ij the cotan weights of the
// rest triangles. Alternates the local step (one rotation per vertex, fixed
// ones included, since they enter the right-hand side of their free
// neighbours) and the global step (the cotan Laplacian over the free vertices,
// factored once, solved for the three coordinates in one pass).
//
// The rest shape is planar, so only the first two columns of each rotation
// act on it, and they have a closed form: the polar factor of a 3 x 2 matrix
// (below), about ten times cheaper than a 3 x 3 SVD.
//
// The result only starts the energy minimisation, so the iterations stop once
// no free vertex moves more than ArapOptions::tolerance (in mean rest edge
// lengths) in one iteration. Both steps are linear in the weighted rest edges
// w_ij (p_i - p_j), whose per-vertex sums are constant: an iteration costs
// one pass over the half-edges per step, plus the solve. On large patches
// both passes run on the OpenMP threads available (kSmallestParallelDomain).
#include "foldfill/arap.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "embed/coordinate_cholesky.h"
#include "foldfill/error.h"

namespace foldfill {
namespace {

// Negative cotan weights (obtuse angles facing an edge on both sides) make the
// Laplacian indefinite; they are clamped to this small positive value, which
// keeps the system positive definite and changes nothing on Delaunay patches.
constexpr double kMinCotanWeight = 1e-3;

// The local step and the right-hand side are per-vertex sums, each on one
// thread, so the result does not depend on the thread count. Below this many
// free vertices the loops run on one thread: a second one saves nothing
// there, and on a loaded machine each loop would wait for a descheduled
// thread (docs/benchmarks.md, "Figures behind the code's choices").
constexpr int kSmallestParallelDomain = 5000;

// The one-ring of every vertex as flat arrays (compressed rows): for the k-th
// half-edge i -> neighbour[k], its weight w_ij and the weighted rest edge
// vector w_ij (p_i - p_j) (the rest shape is planar: z = 0).
struct Neighbourhoods {
  std::vector<int> offset;  // vertex i owns half-edges [offset[i], offset[i + 1])
  std::vector<int> neighbour;
  std::vector<double> weight;
  std::vector<Eigen::Vector2d> weighted_rest_edge;
  std::vector<Eigen::Vector2d> weighted_rest_edge_sum;  // per vertex, over its half-edges
  std::vector<int> rotated;      // the vertices whose rotation the global step uses
  double mean_rest_edge_length;  // of the flat domain, before shrinking
};

using Points = CoordinateCholesky<double>::Coordinates;
using Frame = Eigen::Matrix<double, 3, 2>;  // the first two columns of a rotation

void check_domain(const EmbedDomain& domain) {
  const int n = domain.vertex_count();
  if (domain.fixed_count < 0 || domain.fixed_count > n ||
      static_cast<int>(domain.fixed_positions.size()) != domain.fixed_count)
    throw InternalError("arap: fixed vertex count does not match the domain");
  for (const Tri& f : domain.faces)
    for (int v : f)
      if (v < 0 || v >= n) throw InternalError("arap: face index out of range");
  for (const Vec3& p : domain.fixed_positions)
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw NonFiniteCoordinateError("arap: a fixed position is not finite");
}

double cotangent(const Vec2& apex, const Vec2& a, const Vec2& b) {
  const double ux = a[0] - apex[0], uy = a[1] - apex[1];
  const double vx = b[0] - apex[0], vy = b[1] - apex[1];
  const double cross = ux * vy - uy * vx;
  const double dot = ux * vx + uy * vy;
  // A degenerate rest triangle gives no information: weight it as a right angle.
  return cross > 0 ? dot / cross : 0.0;
}

// The half-edges of the domain's faces, grouped by their `from` vertex
// (compressed rows: vertex i's are [start[i], start[i + 1])) and sorted by
// their `to` vertex within a group; an interior edge comes twice in each
// direction, once per face.
struct HalfEdge {
  int to;
  double weight;  // half the cotangent of the angle facing it in its face
};

std::vector<HalfEdge> half_edges_by_vertex(const EmbedDomain& domain, std::vector<int>& start) {
  const int n = domain.vertex_count();
  start.assign(n + 1, 0);
  for (const Tri& f : domain.faces)
    for (int v : f) start[v + 1] += 2;
  for (int i = 0; i < n; ++i) start[i + 1] += start[i];
  std::vector<int> cursor(start.begin(), start.end() - 1);
  std::vector<HalfEdge> half_edges(start[n]);
  for (const Tri& f : domain.faces) {
    for (int k = 0; k < 3; ++k) {
      const int i = f[(k + 1) % 3], j = f[(k + 2) % 3];
      const double w = 0.5 * cotangent(domain.rest_uv[f[k]], domain.rest_uv[i], domain.rest_uv[j]);
      half_edges[cursor[i]++] = {j, w};
      half_edges[cursor[j]++] = {i, w};
    }
  }
  for (int i = 0; i < n; ++i)
    std::sort(half_edges.begin() + start[i], half_edges.begin() + start[i + 1],
              [](const HalfEdge& a, const HalfEdge& b) { return a.to < b.to; });
  return half_edges;
}

// Half the sum of the cotangents of the angles facing each edge, clamped.
Neighbourhoods build_neighbourhoods(const EmbedDomain& domain, double shrink) {
  const int n = domain.vertex_count();
  std::vector<int> start;
  const std::vector<HalfEdge> half_edges = half_edges_by_vertex(domain, start);

  Neighbourhoods hood;
  hood.offset.assign(n + 1, 0);
  hood.neighbour.reserve(half_edges.size() / 2);  // interior edges come twice
  hood.weight.reserve(half_edges.size() / 2);
  hood.weighted_rest_edge.reserve(half_edges.size() / 2);
  hood.weighted_rest_edge_sum.assign(n, Eigen::Vector2d::Zero());
  double length_sum = 0;
  for (int i = 0; i < n; ++i) {
    for (int k = start[i]; k < start[i + 1];) {
      const int j = half_edges[k].to;
      double w = 0;  // the edge's one or two half-weights (a + b rounds as b + a)
      for (; k < start[i + 1] && half_edges[k].to == j; ++k) w += half_edges[k].weight;
      const Eigen::Vector2d rest_edge(domain.rest_uv[i][0] - domain.rest_uv[j][0],
                                      domain.rest_uv[i][1] - domain.rest_uv[j][1]);
      const double clamped = std::max(w, kMinCotanWeight);
      hood.neighbour.push_back(j);
      hood.weight.push_back(clamped);
      hood.weighted_rest_edge.push_back(clamped * shrink * rest_edge);
      hood.weighted_rest_edge_sum[i] += hood.weighted_rest_edge.back();
      length_sum += rest_edge.norm();
      ++hood.offset[i + 1];
    }
  }
  for (int i = 0; i < n; ++i) hood.offset[i + 1] += hood.offset[i];
  hood.mean_rest_edge_length = hood.neighbour.empty() ? 0 : length_sum / hood.neighbour.size();

  // Free vertices and the fixed ones next to them (the loop): the strip's
  // outer ring touches fixed vertices only, and its rotations are never used.
  std::vector<char> used(n, 0);
  for (int i = domain.fixed_count; i < n; ++i) {
    used[i] = 1;
    for (int k = hood.offset[i]; k < hood.offset[i + 1]; ++k) used[hood.neighbour[k]] = 1;
  }
  for (int i = 0; i < n; ++i)
    if (used[i]) hood.rotated.push_back(i);
  return hood;
}

// The best similarity taking the flat loop (u, v, 0) onto its 3D positions,
// applied to the whole flat domain; fixed vertices are then put in place.
Points initial_guess(const EmbedDomain& domain) {
  const int n = domain.vertex_count();
  const int fit_count = domain.loop_size >= 3 ? domain.loop_size : domain.fixed_count;
  Points x(n, 3);
  for (int i = 0; i < n; ++i) x.row(i) << domain.rest_uv[i][0], domain.rest_uv[i][1], 0.0;
  if (fit_count >= 3) {
    Eigen::Matrix3Xd flat(3, fit_count), placed(3, fit_count);
    for (int i = 0; i < fit_count; ++i) {
      flat.col(i) = x.row(i).transpose();
      placed.col(i) = Eigen::Vector3d(domain.fixed_positions[i].data());
    }
    const Eigen::Matrix4d similarity = Eigen::umeyama(flat, placed, true);
    // A degenerate loop (all points on a line) has no best similarity: then
    // the flat patch itself is the start.
    if (similarity.allFinite())
      x = ((x * similarity.topLeftCorner<3, 3>().transpose()).rowwise() +
           similarity.topRightCorner<3, 1>().transpose())
              .eval();
  }
  for (int i = 0; i < domain.fixed_count; ++i)
    x.row(i) = Eigen::RowVector3d(domain.fixed_positions[i].data());
  return x;
}

// A unit vector orthogonal to the unit vector `u`.
Eigen::Vector3d orthogonal_to(const Eigen::Vector3d& u) {
  Eigen::Index smallest;
  u.cwiseAbs().minCoeff(&smallest);
  return u.cross(Eigen::Vector3d::Unit(smallest)).normalized();
}

// The orthonormal 3 x 2 frame Q maximising trace(Q^T C): the polar factor
// of C, from the eigenvectors v1, v2 of the 2 x 2 matrix C^T C: Q = u1 v1^T +
// u2 v2^T with u_k = C v_k / |C v_k|. u2 is made orthogonal to u1 explicitly,
// and chosen freely when C has rank 1 (then any choice is optimal).
Frame polar_factor(const Frame& c) {
  const double a = c.col(0).squaredNorm(), b = c.col(0).dot(c.col(1));
  const double d = c.col(1).squaredNorm();
  if (!(a + d > 0)) return Frame::Identity();  // no information: keep the rest orientation
  // Largest eigenvalue and its eigenvector, from the better conditioned of
  // the two rows of C^T C - largest I. (The squares cannot overflow: they
  // are of squared lengths of normalised coordinates; hypot costs 5x more.)
  const double half_gap = 0.5 * (a - d);
  const double largest = 0.5 * (a + d) + std::sqrt(half_gap * half_gap + b * b);
  Eigen::Vector2d v1 = std::abs(a - largest) > std::abs(d - largest)
                           ? Eigen::Vector2d(-b, a - largest)
                           : Eigen::Vector2d(d - largest, -b);
  const double v1_norm = v1.norm();
  v1 = v1_norm > 0 ? Eigen::Vector2d(v1 / v1_norm) : Eigen::Vector2d(1, 0);  // C^T C = a I
  const Eigen::Vector2d v2(-v1[1], v1[0]);
  const Eigen::Vector3d u1 = (c * v1).normalized();
  Eigen::Vector3d u2 = c * v2;
  u2 -= u1.dot(u2) * u1;
  const double u2_norm = u2.norm();
  u2 = u2_norm > 1e-12 * std::sqrt(largest) ? Eigen::Vector3d(u2 / u2_norm) : orthogonal_to(u1);
  return u1 * v1.transpose() + u2 * v2.transpose();
}

// Local step: per vertex whose rotation is used, the frame of the rotation
// that best fits its weighted one-ring, from C_i = sum_j (x_i - x_j) e_ij^T
// = x_i (sum_j e_ij)^T - sum_j x_j e_ij^T, e_ij = w_ij (p_i - p_j).
void fit_rotations(const Neighbourhoods& hood, const Points& x, std::vector<Frame>& frames) {
  const int count = static_cast<int>(hood.rotated.size());
#pragma omp parallel for schedule(static) if (count >= kSmallestParallelDomain)
  for (int r = 0; r < count; ++r) {
    const int i = hood.rotated[r];
    Frame neighbours = Frame::Zero();
    for (int k = hood.offset[i]; k < hood.offset[i + 1]; ++k)
      neighbours.noalias() +=
          x.row(hood.neighbour[k]).transpose() * hood.weighted_rest_edge[k].transpose();
    frames[i] = polar_factor(x.row(i).transpose() * hood.weighted_rest_edge_sum[i].transpose() -
                             neighbours);
  }
}

// The free-free block of the cotan Laplacian, factored, and per free vertex
// the constant right-hand side contributed by its fixed neighbours.
struct GlobalSystem {
  std::optional<CoordinateCholesky<double>> factor;
  Points fixed_rhs;
};

void build_global_system(const EmbedDomain& domain, const Neighbourhoods& hood,
                         GlobalSystem& system) {
  const int fixed = domain.fixed_count;
  const int free_count = domain.free_count();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(hood.neighbour.size() + free_count);
  system.fixed_rhs = Points::Zero(free_count, 3);
  for (int i = fixed; i < domain.vertex_count(); ++i) {
    double diagonal = 0;
    for (int k = hood.offset[i]; k < hood.offset[i + 1]; ++k) {
      const int j = hood.neighbour[k];
      diagonal += hood.weight[k];
      if (j >= fixed)
        entries.emplace_back(i - fixed, j - fixed, -hood.weight[k]);
      else
        system.fixed_rhs.row(i - fixed) +=
            hood.weight[k] * Eigen::RowVector3d(domain.fixed_positions[j].data());
    }
    entries.emplace_back(i - fixed, i - fixed, diagonal);
  }
  Eigen::SparseMatrix<double> laplacian(free_count, free_count);
  laplacian.setFromTriplets(entries.begin(), entries.end());
  system.factor.emplace(laplacian, OrderingEffort::Quick,
                        "arap: the patch has free vertices not connected to the fixed strip");
}

// Global step: L_ff x_f = sum_j (R_i + R_j) e_ij / 2 + fixed terms, with
// sum_j R_i e_ij = R_i sum_j e_ij. Solves into `next`, moves the free
// vertices of `x` there and returns the largest distance one of them moved.
double solve_positions(const EmbedDomain& domain, const Neighbourhoods& hood,
                       const std::vector<Frame>& frames, const GlobalSystem& system, Points& next,
                       Points& x) {
  const int fixed = domain.fixed_count;
  next = system.fixed_rhs;
  const int count = domain.vertex_count();
#pragma omp parallel for schedule(static) if (count - fixed >= kSmallestParallelDomain)
  for (int i = fixed; i < count; ++i) {
    Eigen::Vector3d sum = frames[i] * hood.weighted_rest_edge_sum[i];
    for (int k = hood.offset[i]; k < hood.offset[i + 1]; ++k)
      sum.noalias() += frames[hood.neighbour[k]] * hood.weighted_rest_edge[k];
    next.row(i - fixed) += 0.5 * sum.transpose();
  }
  system.factor->solve(next, next);
  double largest_squared_move = 0;
  for (int i = fixed; i < domain.vertex_count(); ++i) {
    const double squared_move = (next.row(i - fixed) - x.row(i)).squaredNorm();
    // Finite positions give a finite move (the comparison fails on NaN).
    if (!(squared_move < std::numeric_limits<double>::infinity()))
      throw FillFailedError("arap: the solve gave non-finite positions");
    largest_squared_move = std::max(largest_squared_move, squared_move);
    x.row(i) = next.row(i - fixed);
  }
  return std::sqrt(largest_squared_move);
}

}  // namespace

std::vector<Vec3> membrane_embed(const EmbedDomain& domain) {
  check_domain(domain);
  std::vector<Vec3> positions(domain.fixed_positions);
  if (domain.free_count() == 0) return positions;
  const Neighbourhoods hood = build_neighbourhoods(domain, 1.0);
  GlobalSystem system;
  build_global_system(domain, hood, system);
  Points x = system.fixed_rhs;
  system.factor->solve(x, x);
  positions.reserve(domain.vertex_count());
  for (int i = 0; i < domain.free_count(); ++i) positions.push_back({x(i, 0), x(i, 1), x(i, 2)});
  return positions;
}

std::vector<Vec3> arap_embed(const EmbedDomain& domain, const ArapOptions& options,
                             const Budget& budget) {
  check_domain(domain);
  if (!(options.shrink > 0)) throw UsageError("arap: the shrink factor must be positive");
  if (!(options.tolerance >= 0)) throw UsageError("arap: the tolerance must not be negative");
  Points x = initial_guess(domain);

  if (domain.free_count() > 0 && options.iterations > 0 && !budget.spent()) {
    const Neighbourhoods hood = build_neighbourhoods(domain, options.shrink);
    GlobalSystem system;
    build_global_system(domain, hood, system);
    std::vector<Frame> frames(domain.vertex_count());
    Points next;
    const double stop_move = options.tolerance * hood.mean_rest_edge_length;
    for (int iteration = 0; iteration < options.iterations && !budget.spent(); ++iteration) {
      fit_rotations(hood, x, frames);
      if (solve_positions(domain, hood, frames, system, next, x) <= stop_move) break;
    }
  }

  std::vector<Vec3> positions(domain.fixed_positions);
  positions.reserve(domain.vertex_count());
  for (int i = domain.fixed_count; i < domain.vertex_count(); ++i)
    positions.push_back({x(i, 0), x(i, 1), x(i, 2)});
  return positions;
}

}  // namespace foldfill
