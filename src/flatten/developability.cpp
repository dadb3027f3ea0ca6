// The developability of a hole's surroundings (see developability.h).
// Discrete curvatures at a vertex i with area A_i (a third of its faces'):
// Gaussian K_i = (2 pi - angle sum) / A_i, mean H_i = sum over its edges of
// dihedral angle * length / (4 A_i). Their ratio over the ring cancels the
// resolution; the signed sum of K keeps noise (whose K has either sign) from
// passing for curvature.
#include "foldfill/developability.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "foldfill/vec3.h"

namespace foldfill {
namespace {

// Whether every edge at `v` has two faces (v is interior).
bool is_interior(const Mesh& mesh, const VertexFaces& vertex_faces, int v) {
  // Each neighbour w must be reached once as "next" and once as "previous".
  std::vector<std::pair<int, int>> count;
  for (int k = vertex_faces.start[v]; k < vertex_faces.start[v + 1]; ++k) {
    const Tri& f = mesh.faces[vertex_faces.faces[k]];
    const int c = f[0] == v ? 0 : f[1] == v ? 1 : 2;
    count.emplace_back(f[(c + 1) % 3], 1);
    count.emplace_back(f[(c + 2) % 3], -1);
  }
  std::sort(count.begin(), count.end());
  for (size_t i = 0; i < count.size();) {
    int sum = 0;
    size_t j = i;
    for (; j < count.size() && count[j].first == count[i].first; ++j) sum += count[j].second;
    if (sum != 0 || j - i != 2) return false;
    i = j;
  }
  return !count.empty();
}

}  // namespace

Developability measure_developability(const Mesh& mesh, const VertexFaces& vertex_faces,
                                      const BoundaryLoop& loop) {
  std::vector<int> on_loop = loop.vertices;
  std::sort(on_loop.begin(), on_loop.end());
  // The strip's outer ring: the loop vertices' neighbours off the loop.
  std::vector<int> ring;
  for (int v : loop.vertices)
    for (int k = vertex_faces.start[v]; k < vertex_faces.start[v + 1]; ++k)
      for (int w : mesh.faces[vertex_faces.faces[k]])
        if (!std::binary_search(on_loop.begin(), on_loop.end(), w)) ring.push_back(w);
  std::sort(ring.begin(), ring.end());
  ring.erase(std::unique(ring.begin(), ring.end()), ring.end());

  Developability result;
  double gaussian = 0, mean2 = 0, area = 0;
  for (int v : ring) {
    if (!is_interior(mesh, vertex_faces, v)) continue;
    double angle_sum = 0, a = 0, dihedral_length = 0;
    for (int k = vertex_faces.start[v]; k < vertex_faces.start[v + 1]; ++k) {
      const Tri& f = mesh.faces[vertex_faces.faces[k]];
      const int c = f[0] == v ? 0 : f[1] == v ? 1 : 2;
      const Vec3& p = mesh.positions[v];
      const Vec3 u = sub(mesh.positions[f[(c + 1) % 3]], p);
      const Vec3 w = sub(mesh.positions[f[(c + 2) % 3]], p);
      const Vec3 n = cross(u, w);
      const double twice_area = std::sqrt(dot(n, n));
      angle_sum += std::atan2(twice_area, dot(u, w));
      a += twice_area / 6;
      // The edge v -> next is shared with the face that has next -> v.
      const int next = f[(c + 1) % 3];
      for (int m = vertex_faces.start[v]; m < vertex_faces.start[v + 1]; ++m) {
        const Tri& g = mesh.faces[vertex_faces.faces[m]];
        const int d = g[0] == v ? 0 : g[1] == v ? 1 : 2;
        if (g[(d + 2) % 3] != next) continue;
        const Vec3 n2 = cross(sub(mesh.positions[g[(d + 1) % 3]], p), sub(mesh.positions[next], p));
        const double norms = twice_area * std::sqrt(dot(n2, n2));
        if (norms > 0)
          dihedral_length +=
              std::acos(std::clamp(dot(n, n2) / norms, -1.0, 1.0)) * std::sqrt(dot(u, u));
      }
    }
    if (!(a > 0)) continue;
    const double h = dihedral_length / (4 * a);
    gaussian += 2 * M_PI - angle_sum;
    mean2 += h * h * a;
    area += a;
    ++result.samples;
  }
  if (result.samples == 0 || !(area > 0)) return result;
  const double hole_area = loop.length * loop.length / (4 * M_PI);
  result.predicted_curvature = std::abs(gaussian) / area * hole_area;
  // Surroundings flatter than a degree of bending over the hole count as flat.
  const double flat = 1e-4 / hole_area;
  result.ratio = mean2 / area > flat ? std::abs(gaussian) / mean2 : 0;
  return result;
}

}  // namespace foldfill
