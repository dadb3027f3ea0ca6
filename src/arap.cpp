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
#include "foldfill/arap.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include "coordinate_cholesky.h"
#include "foldfill/error.h"

namespace foldfill {
namespace {

// Negative cotan weights (obtuse angles facing an edge on both sides) make the
// Laplacian indefinite; they are clamped to this small positive value, which
// keeps the system positive definite and changes nothing on Delaunay patches.
constexpr double kMinCotanWeight = 1e-3;

// The one-ring of every vertex as flat arrays (compressed rows): for the k-th
// half-edge i -> neighbour[k], its weight and the rest edge vector p_i - p_j.
struct Neighbourhoods {
  std::vector<int> offset;  // vertex i owns half-edges [offset[i], offset[i + 1])
  std::vector<int> neighbour;
  std::vector<double> weight;
  std::vector<Eigen::Vector2d> rest_edge;  // rest shape is planar: z = 0
};

using Points = CoordinateCholesky<double>::Coordinates;
using Frame = Eigen::Matrix<double, 3, 2>;  // the first two columns of a rotation

void check_domain(const EmbedDomain& domain) {
  const int n = domain.vertex_count();
  if (domain.fixed_count < 0 || domain.fixed_count > n ||
      static_cast<int>(domain.fixed_positions.size()) != domain.fixed_count)
    throw Error(ErrorKind::Internal, "arap: fixed vertex count does not match the domain");
  for (const Tri& f : domain.faces)
    for (int v : f)
      if (v < 0 || v >= n) throw Error(ErrorKind::Internal, "arap: face index out of range");
  for (const Vec3& p : domain.fixed_positions)
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw Error(ErrorKind::NonFiniteCoordinate, "arap: a fixed position is not finite");
}

double cotangent(const Vec2& apex, const Vec2& a, const Vec2& b) {
  const double ux = a[0] - apex[0], uy = a[1] - apex[1];
  const double vx = b[0] - apex[0], vy = b[1] - apex[1];
  const double cross = ux * vy - uy * vx;
  const double dot = ux * vx + uy * vy;
  // A degenerate rest triangle gives no information: weight it as a right angle.
  return cross > 0 ? dot / cross : 0.0;
}

// Half the sum of the cotangents of the angles facing each edge, clamped.
Neighbourhoods build_neighbourhoods(const EmbedDomain& domain, double shrink) {
  const int n = domain.vertex_count();
  struct HalfEdge {
    int from, to;
    double weight;
  };
  std::vector<HalfEdge> half_edges;
  half_edges.reserve(6 * domain.faces.size());
  for (const Tri& f : domain.faces) {
    for (int k = 0; k < 3; ++k) {
      const int i = f[(k + 1) % 3], j = f[(k + 2) % 3];
      const double w = 0.5 * cotangent(domain.rest_uv[f[k]], domain.rest_uv[i], domain.rest_uv[j]);
      half_edges.push_back({i, j, w});
      half_edges.push_back({j, i, w});
    }
  }
  std::sort(half_edges.begin(), half_edges.end(), [](const HalfEdge& a, const HalfEdge& b) {
    return a.from != b.from ? a.from < b.from : a.to < b.to;
  });

  Neighbourhoods hood;
  hood.offset.assign(n + 1, 0);
  for (size_t k = 0; k < half_edges.size();) {
    size_t end = k;
    double w = 0;
    for (; end < half_edges.size() && half_edges[end].from == half_edges[k].from &&
           half_edges[end].to == half_edges[k].to;
         ++end)
      w += half_edges[end].weight;
    const int i = half_edges[k].from, j = half_edges[k].to;
    hood.neighbour.push_back(j);
    hood.weight.push_back(std::max(w, kMinCotanWeight));
    hood.rest_edge.emplace_back(shrink * (domain.rest_uv[i][0] - domain.rest_uv[j][0]),
                                shrink * (domain.rest_uv[i][1] - domain.rest_uv[j][1]));
    ++hood.offset[i + 1];
    k = end;
  }
  for (int i = 0; i < n; ++i) hood.offset[i + 1] += hood.offset[i];
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
  // the two rows of C^T C - largest I.
  const double largest = 0.5 * (a + d) + std::hypot(0.5 * (a - d), b);
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

// Local step: per vertex, the frame of the rotation that best fits its
// weighted one-ring, from C_i = sum_j w_ij (x_i - x_j)(p_i - p_j)^T.
void fit_rotations(const Neighbourhoods& hood, const Points& x, std::vector<Frame>& frames) {
  const int n = static_cast<int>(x.rows());
  for (int i = 0; i < n; ++i) {
    Frame covariance = Frame::Zero();
    for (int k = hood.offset[i]; k < hood.offset[i + 1]; ++k) {
      const Eigen::Vector3d deformed = (x.row(i) - x.row(hood.neighbour[k])).transpose();
      covariance.noalias() += (hood.weight[k] * deformed) * hood.rest_edge[k].transpose();
    }
    frames[i] = polar_factor(covariance);
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

// Global step: L_ff x_f = sum_j w_ij / 2 (R_i + R_j)(p_i - p_j) + fixed terms.
void solve_positions(const EmbedDomain& domain, const Neighbourhoods& hood,
                     const std::vector<Frame>& frames, const GlobalSystem& system, Points& rhs,
                     Points& x) {
  const int fixed = domain.fixed_count;
  rhs = system.fixed_rhs;
  for (int i = fixed; i < domain.vertex_count(); ++i) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int k = hood.offset[i]; k < hood.offset[i + 1]; ++k) {
      sum.noalias() +=
          (frames[i] + frames[hood.neighbour[k]]) * (0.5 * hood.weight[k] * hood.rest_edge[k]);
    }
    rhs.row(i - fixed) += sum.transpose();
  }
  auto free_rows = x.bottomRows(domain.free_count());
  system.factor->solve(rhs, free_rows);
  if (!free_rows.allFinite())
    throw Error(ErrorKind::FillFailed, "arap: the solve gave non-finite positions");
}

}  // namespace

std::vector<Vec3> arap_embed(const EmbedDomain& domain, const ArapOptions& options) {
  check_domain(domain);
  if (!(options.shrink > 0))
    throw Error(ErrorKind::Usage, "arap: the shrink factor must be positive");
  Points x = initial_guess(domain);

  if (domain.free_count() > 0 && options.iterations > 0) {
    const Neighbourhoods hood = build_neighbourhoods(domain, options.shrink);
    GlobalSystem system;
    build_global_system(domain, hood, system);
    std::vector<Frame> frames(domain.vertex_count());
    Points rhs;
    for (int iteration = 0; iteration < options.iterations; ++iteration) {
      fit_rotations(hood, x, frames);
      solve_positions(domain, hood, frames, system, rhs, x);
    }
  }

  std::vector<Vec3> positions(domain.fixed_positions);
  positions.reserve(domain.vertex_count());
  for (int i = domain.fixed_count; i < domain.vertex_count(); ++i)
    positions.push_back({x(i, 0), x(i, 1), x(i, 2)});
  return positions;
}

}  // namespace foldfill
