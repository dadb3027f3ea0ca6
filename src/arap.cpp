// As-rigid-as-possible embedding (Sorkine & Alexa 2007) of the domain with a
// shrunk rest shape, the initialisation of section 3.3 of Gisbert et al. 2023.
//
// Energy: sum_i sum_{j in N(i)} w_ij |(x_i - x_j) - R_i (p_i - p_j)|^2 with p
// the rest shape (flat uv scaled by c, z = 0) and w_ij the cotan weights of the
// rest triangles. Alternates the local step (one rotation per vertex, fixed
// ones included, since they enter the right-hand side of their free
// neighbours) and the global step (the cotan Laplacian over the free vertices,
// factored once).
#include "foldfill/arap.h"

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <string>

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
Eigen::MatrixX3d initial_guess(const EmbedDomain& domain) {
  const int n = domain.vertex_count();
  const int fit_count = domain.loop_size >= 3 ? domain.loop_size : domain.fixed_count;
  Eigen::MatrixX3d x(n, 3);
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

// Local step: R_i = argmin over rotations of the vertex's weighted one-ring
// fit, from the SVD of S_i = sum_j w_ij (p_i - p_j)(x_i - x_j)^T.
void fit_rotations(const Neighbourhoods& hood, const Eigen::MatrixX3d& x,
                   std::vector<Eigen::Matrix3d>& rotations) {
  const int n = static_cast<int>(x.rows());
  for (int i = 0; i < n; ++i) {
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    for (int k = hood.offset[i]; k < hood.offset[i + 1]; ++k) {
      const Eigen::RowVector3d deformed = x.row(i) - x.row(hood.neighbour[k]);
      covariance.topRows<2>() += hood.weight[k] * hood.rest_edge[k] * deformed;
    }
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance,
                                                Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d v = svd.matrixV();
    // A reflection is turned into the nearest rotation by flipping the axis of
    // the smallest singular value (the last: Eigen sorts them decreasingly).
    if ((v * svd.matrixU().transpose()).determinant() < 0) v.col(2) = -v.col(2);
    rotations[i] = v * svd.matrixU().transpose();
  }
}

// The free-free block of the cotan Laplacian and, per free vertex, the
// constant right-hand side contributed by its fixed neighbours.
struct GlobalSystem {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor;
  Eigen::MatrixX3d fixed_rhs;
};

void build_global_system(const EmbedDomain& domain, const Neighbourhoods& hood,
                         GlobalSystem& system) {
  const int fixed = domain.fixed_count;
  const int free_count = domain.free_count();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(hood.neighbour.size() + free_count);
  system.fixed_rhs = Eigen::MatrixX3d::Zero(free_count, 3);
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
  system.factor.compute(laplacian);
  if (system.factor.info() != Eigen::Success)
    throw Error(ErrorKind::FillFailed,
                "arap: the patch has free vertices not connected to the fixed strip");
}

// Global step: L_ff x_f = sum_j w_ij / 2 (R_i + R_j)(p_i - p_j) + fixed terms.
void solve_positions(const EmbedDomain& domain, const Neighbourhoods& hood,
                     const std::vector<Eigen::Matrix3d>& rotations, const GlobalSystem& system,
                     Eigen::MatrixX3d& x) {
  const int fixed = domain.fixed_count;
  Eigen::MatrixX3d rhs = system.fixed_rhs;
  for (int i = fixed; i < domain.vertex_count(); ++i) {
    for (int k = hood.offset[i]; k < hood.offset[i + 1]; ++k) {
      const Eigen::Matrix<double, 3, 2> rotation_sum =
          (rotations[i] + rotations[hood.neighbour[k]]).leftCols<2>();
      rhs.row(i - fixed) += (0.5 * hood.weight[k] * rotation_sum * hood.rest_edge[k]).transpose();
    }
  }
  x.bottomRows(domain.free_count()) = system.factor.solve(rhs);
  if (!x.allFinite())
    throw Error(ErrorKind::FillFailed, "arap: the solve gave non-finite positions");
}

}  // namespace

std::vector<Vec3> arap_embed(const EmbedDomain& domain, const ArapOptions& options) {
  check_domain(domain);
  if (!(options.shrink > 0))
    throw Error(ErrorKind::Usage, "arap: the shrink factor must be positive");
  Eigen::MatrixX3d x = initial_guess(domain);

  if (domain.free_count() > 0 && options.iterations > 0) {
    const Neighbourhoods hood = build_neighbourhoods(domain, options.shrink);
    GlobalSystem system;
    build_global_system(domain, hood, system);
    std::vector<Eigen::Matrix3d> rotations(domain.vertex_count());
    for (int iteration = 0; iteration < options.iterations; ++iteration) {
      fit_rotations(hood, x, rotations);
      solve_positions(domain, hood, rotations, system, x);
    }
  }

  std::vector<Vec3> positions(domain.fixed_positions);
  positions.reserve(domain.vertex_count());
  for (int i = domain.fixed_count; i < domain.vertex_count(); ++i)
    positions.push_back({x(i, 0), x(i, 1), x(i, 2)});
  return positions;
}

}  // namespace foldfill
