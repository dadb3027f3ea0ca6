// Surfaces with holes cut out, for the tests of hole selection. Each surface
// is built whole, then the holes are cut as regions of removed faces
// (SurfaceCut), cleaned so that every region's boundary is one simple loop,
// and the mesh is compacted.
#include "foldfill/test_surfaces.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <queue>
#include <random>
#include <utility>

#include "foldfill/examples.h"
#include "foldfill/topology.h"
#include "foldfill/vec3.h"

namespace foldfill {
namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3 operator+(const Vec3& a, const Vec3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
Vec3 operator-(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 operator*(double s, const Vec3& a) { return {s * a[0], s * a[1], s * a[2]}; }
Vec3 normalized(const Vec3& a) { return (1 / norm(a)) * a; }
double angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(norm(cross(a, b)), dot(a, b));
}

Vec3 centroid(const Mesh& mesh, const Tri& f) {
  return (1.0 / 3) * (mesh.positions[f[0]] + mesh.positions[f[1]] + mesh.positions[f[2]]);
}

// A unit sphere: an icosahedron whose faces are split `subdivisions` times
// into four, every vertex projected onto the sphere. Faces are
// counter-clockwise seen from outside.
Mesh icosphere(int subdivisions) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  Mesh mesh;
  mesh.positions = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                    {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  mesh.faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (Vec3& p : mesh.positions) p = normalized(p);
  for (int level = 0; level < subdivisions; ++level) {
    std::map<std::pair<int, int>, int> midpoint;
    const auto middle = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto [it, inserted] = midpoint.emplace(key, mesh.vertex_count());
      if (inserted) {
        mesh.positions.push_back(normalized(mesh.positions[a] + mesh.positions[b]));
      }
      return it->second;
    };
    std::vector<Tri> faces;
    faces.reserve(4 * mesh.faces.size());
    for (const Tri& f : mesh.faces) {
      const int ab = middle(f[0], f[1]), bc = middle(f[1], f[2]), ca = middle(f[2], f[0]);
      faces.push_back({f[0], ab, ca});
      faces.push_back({f[1], bc, ab});
      faces.push_back({f[2], ca, bc});
      faces.push_back({ab, bc, ca});
    }
    mesh.faces = std::move(faces);
  }
  // The classic vertex list above is wound either way depending on its
  // source; orient every face outwards.
  for (Tri& f : mesh.faces) {
    const Vec3 n = cross(mesh.positions[f[1]] - mesh.positions[f[0]],
                         mesh.positions[f[2]] - mesh.positions[f[0]]);
    if (dot(n, centroid(mesh, f)) < 0) std::swap(f[1], f[2]);
  }
  return mesh;
}

int segments_for(double length, double edge_length) {
  return std::max(3, static_cast<int>(std::lround(length / edge_length)));
}

// A uniform number in [0, 1) from a generator whose sequence the standard
// fixes, so that the surfaces are the same on every platform.
double uniform(std::mt19937_64& random) { return static_cast<double>(random() >> 11) * 0x1.0p-53; }

// Regions of removed faces on a mesh: the holes and the open parts cut from a
// whole surface.
class SurfaceCut {
 public:
  explicit SurfaceCut(Mesh mesh)
      : mesh_(std::move(mesh)),
        vertex_faces_(build_vertex_faces(mesh_.faces, mesh_.vertex_count())),
        topology_(build_edge_topology(mesh_.faces, mesh_.vertex_count())),
        region_(mesh_.faces.size(), -1),
        neighbours_(mesh_.positions.size()) {
    for (const Edge& e : topology_.edges) {
      neighbours_[e.v0].push_back(e.v1);
      neighbours_[e.v1].push_back(e.v0);
    }
  }

  const Mesh& mesh() const { return mesh_; }

  // A new region: `hole` (a hole to fill) or not (an open part, whose loop is
  // an edge), cleaned or kept exactly as cut.
  int add_region(bool hole, bool clean = true) {
    is_hole_.push_back(hole);
    clean_.push_back(clean);
    return static_cast<int>(is_hole_.size()) - 1;
  }

  // Removes, into `region`, the kept faces for which `inside` holds.
  void remove_where(int region, const std::function<bool(int face)>& inside) {
    for (int f = 0; f < mesh_.face_count(); ++f) {
      if (region_[f] < 0 && inside(f)) region_[f] = region;
    }
  }

  // Removes the faces whose centroid lies within `radius` of `source` along
  // the mesh: the distance through the nearest of the face's vertices, the
  // vertices' distances found by Dijkstra along the edges (a little longer
  // than the geodesic one).
  void remove_geodesic_disk(int region, int source, double radius) {
    const std::vector<double> distance = edge_distances(source, 2 * radius);
    remove_where(region, [&](int f) {
      const Tri& face = mesh_.faces[f];
      const Vec3 c = centroid(mesh_, face);
      double d = std::numeric_limits<double>::infinity();
      for (int v : face) d = std::min(d, distance[v] + norm(c - mesh_.positions[v]));
      return d < radius;
    });
  }

  // Removes `count` consecutive faces around the interior vertex `v`, from
  // its first face on: 1, 2 or 3 faces leave a loop of 3, 4 or 5 vertices.
  void remove_fan(int region, int v, int count) {
    const std::vector<int> fan = faces_around(v);
    for (int k = 0; k < count && k < static_cast<int>(fan.size()); ++k) region_[fan[k]] = region;
  }

  // The vertex nearest to `point`.
  int nearest_vertex(const Vec3& point) const {
    int best = 0;
    for (int v = 1; v < mesh_.vertex_count(); ++v) {
      if (norm(mesh_.positions[v] - point) < norm(mesh_.positions[best] - point)) best = v;
    }
    return best;
  }

  // The faces around `v` in order (each after the one across its edge from
  // v to the previous face's next vertex).
  std::vector<int> faces_around(int v) const {
    std::vector<int> fan;
    const int begin = vertex_faces_.start[v], end = vertex_faces_.start[v + 1];
    if (begin == end) return fan;
    int f = vertex_faces_.faces[begin];
    for (int step = begin; step < end; ++step) {
      fan.push_back(f);
      const Tri& face = mesh_.faces[f];
      const int k = face[0] == v ? 0 : face[1] == v ? 1 : 2;
      const int next = face[(k + 1) % 3];
      int following = -1;
      for (int i = begin; i < end; ++i) {
        const Tri& other = mesh_.faces[vertex_faces_.faces[i]];
        const int m = other[0] == v ? 0 : other[1] == v ? 1 : 2;
        if (other[(m + 2) % 3] == next) following = vertex_faces_.faces[i];
      }
      if (following < 0 || following == fan.front()) break;
      f = following;
    }
    return fan;
  }

  // Grows the regions to be cleaned until each one's boundary is one simple
  // loop: a kept face with two or three removed neighbours of one region
  // joins it (a notch, or an island), and at a vertex where the kept faces
  // form several fans (the boundary would pass it twice) all but the largest
  // fan join the region there. Each step shortens a boundary, so it ends.
  void clean() {
    for (bool changed = true; changed;) {
      changed = false;
      for (int f = 0; f < mesh_.face_count(); ++f) {
        if (region_[f] >= 0) continue;
        int regions[3], count = 0;
        for (int e : topology_.face_edges[f]) {
          const Edge& edge = topology_.edges[e];
          const int other = edge.face[0] == f ? edge.face[1] : edge.face[0];
          if (other >= 0 && region_[other] >= 0 && clean_[region_[other]]) {
            regions[count++] = region_[other];
          }
        }
        for (int a = 0; a < count; ++a) {
          if (std::count(regions, regions + count, regions[a]) >= 2) {
            region_[f] = regions[a];
            changed = true;
            break;
          }
        }
      }
      for (int v = 0; v < mesh_.vertex_count(); ++v) changed |= unpinch(v);
    }
  }

  // The kept faces, compacted, with a vertex on each region's loop (holes in
  // hole_vertices, open parts in open_vertices, in region order) and, in
  // open_vertices after those, `open_loop_vertices` (vertices of the whole
  // surface on its own boundary loops).
  HoledSurface finish(const std::vector<int>& open_loop_vertices = {}) const {
    std::vector<char> kept_vertex(mesh_.positions.size(), 0);
    for (int f = 0; f < mesh_.face_count(); ++f) {
      if (region_[f] < 0) {
        for (int v : mesh_.faces[f]) kept_vertex[v] = 1;
      }
    }
    std::vector<int> index(mesh_.positions.size(), -1);
    HoledSurface surface;
    for (size_t v = 0; v < index.size(); ++v) {
      if (!kept_vertex[v]) continue;
      index[v] = surface.mesh.vertex_count();
      surface.mesh.positions.push_back(mesh_.positions[v]);
    }
    for (int f = 0; f < mesh_.face_count(); ++f) {
      const Tri& face = mesh_.faces[f];
      if (region_[f] < 0)
        surface.mesh.faces.push_back({index[face[0]], index[face[1]], index[face[2]]});
    }
    for (size_t r = 0; r < is_hole_.size(); ++r) {
      int on_loop = -1;
      for (int f = 0; f < mesh_.face_count() && on_loop < 0; ++f) {
        if (region_[f] != static_cast<int>(r)) continue;
        for (int v : mesh_.faces[f]) {
          if (kept_vertex[v]) on_loop = index[v];
        }
      }
      (is_hole_[r] ? surface.hole_vertices : surface.open_vertices).push_back(on_loop);
    }
    for (int v : open_loop_vertices) surface.open_vertices.push_back(index[v]);
    return surface;
  }

 private:
  std::vector<double> edge_distances(int source, double limit) const {
    std::vector<double> distance(mesh_.positions.size(), std::numeric_limits<double>::infinity());
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    distance[source] = 0;
    queue.push({0, source});
    while (!queue.empty()) {
      const auto [d, v] = queue.top();
      queue.pop();
      if (d > distance[v] || d > limit) continue;
      for (int w : neighbours_[v]) {
        const double through = d + norm(mesh_.positions[w] - mesh_.positions[v]);
        if (through < distance[w]) {
          distance[w] = through;
          queue.push({through, w});
        }
      }
    }
    return distance;
  }

  // At a vertex of a region to clean whose kept faces form several fans, the
  // smaller fans join that region. Returns whether anything changed.
  bool unpinch(int v) {
    int region = -1;
    std::vector<int> kept;
    for (int i = vertex_faces_.start[v]; i < vertex_faces_.start[v + 1]; ++i) {
      const int f = vertex_faces_.faces[i];
      if (region_[f] < 0) {
        kept.push_back(f);
      } else if (clean_[region_[f]] && (region < 0 || region_[f] < region)) {
        region = region_[f];
      }
    }
    if (region < 0 || kept.size() < 2) return false;
    std::vector<int> fan(kept.size());
    std::iota(fan.begin(), fan.end(), 0);
    const auto root = [&](int k) {
      while (fan[k] != k) k = fan[k] = fan[fan[k]];
      return k;
    };
    for (size_t a = 0; a < kept.size(); ++a) {
      for (int e : topology_.face_edges[kept[a]]) {
        const Edge& edge = topology_.edges[e];
        if (edge.v0 != v && edge.v1 != v) continue;
        const int other = edge.face[0] == kept[a] ? edge.face[1] : edge.face[0];
        const auto b = std::find(kept.begin(), kept.end(), other);
        if (b != kept.end())
          fan[root(static_cast<int>(a))] = root(static_cast<int>(b - kept.begin()));
      }
    }
    std::vector<int> size(kept.size(), 0);
    for (size_t k = 0; k < kept.size(); ++k) ++size[root(static_cast<int>(k))];
    const int largest = static_cast<int>(std::max_element(size.begin(), size.end()) - size.begin());
    bool changed = false;
    for (size_t k = 0; k < kept.size(); ++k) {
      if (root(static_cast<int>(k)) != largest) {
        region_[kept[k]] = region;
        changed = true;
      }
    }
    return changed;
  }

  Mesh mesh_;
  VertexFaces vertex_faces_;
  EdgeTopology topology_;
  std::vector<int> region_;  // per face: -1 kept, else the region it was removed into
  std::vector<std::vector<int>> neighbours_;  // per vertex, the vertices it shares an edge with
  std::vector<char> is_hole_, clean_;
};

// The rotation taking a random unit quaternion's frame: a uniformly random
// rotation of space.
std::array<Vec3, 3> random_rotation(std::mt19937_64& random) {
  const double u1 = uniform(random), u2 = 2 * kPi * uniform(random), u3 = 2 * kPi * uniform(random);
  const double w = std::sqrt(1 - u1) * std::sin(u2), x = std::sqrt(1 - u1) * std::cos(u2),
               y = std::sqrt(u1) * std::sin(u3), z = std::sqrt(u1) * std::cos(u3);
  return {{{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
           {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
           {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}}};
}

Vec3 rotate(const std::array<Vec3, 3>& rotation, const Vec3& p) {
  return {dot(rotation[0], p), dot(rotation[1], p), dot(rotation[2], p)};
}

// The direction at `polar` radians from +z, `azimuth` around it.
Vec3 direction(double polar, double azimuth) {
  return {std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
          std::cos(polar)};
}

// The mean length of the edges at `v`.
double mean_edge_length_at(const SurfaceCut& cut, int v) {
  double sum = 0;
  int count = 0;
  for (int f : cut.faces_around(v)) {
    for (int w : cut.mesh().faces[f]) {
      if (w == v) continue;
      sum += norm(cut.mesh().positions[w] - cut.mesh().positions[v]);
      ++count;
    }
  }
  return count > 0 ? sum / count : 0;
}

}  // namespace

HoledSurface make_holed_sphere(const SphereSurfaceOptions& options) {
  Mesh sphere = icosphere(options.subdivisions);
  for (Vec3& p : sphere.positions) p = options.radius * p;
  SurfaceCut cut(std::move(sphere));
  const auto within = [&](const Vec3& centre, double angle) {
    return [&cut, centre, angle](int f) {
      return angle_between(centroid(cut.mesh(), cut.mesh().faces[f]), centre) < angle;
    };
  };
  cut.remove_where(cut.add_region(true), within({0, 0, 1}, options.cap_degrees * kPi / 180));
  for (int k = 0; k < options.small_holes; ++k) {
    const Vec3 centre = direction(130 * kPi / 180, 2 * kPi * (k + 0.25) / options.small_holes);
    cut.remove_where(cut.add_region(true), within(centre, options.small_radius));
  }
  cut.clean();
  return cut.finish();
}

HoledSurface make_holed_torus(const TorusSurfaceOptions& options) {
  const double big = options.major, small = options.minor;
  const int around = segments_for(2 * kPi * big, options.edge_length);
  const int across = segments_for(2 * kPi * small, options.edge_length);
  const auto point = [&](double u, double v) {
    return Vec3{(big + small * std::cos(v)) * std::cos(u),
                (big + small * std::cos(v)) * std::sin(u), small * std::sin(v)};
  };
  Mesh torus;
  for (int j = 0; j < across; ++j) {
    for (int i = 0; i < around; ++i) {
      torus.positions.push_back(point(2 * kPi * i / around, 2 * kPi * j / across));
    }
  }
  // (i, j) -> (u, v): du x dv points outwards.
  torus.faces = grid_triangles(around, across, true, true);
  SurfaceCut cut(std::move(torus));
  for (const auto& [u, v] :
       {std::pair(0.0, 0.0), std::pair(kPi, kPi), std::pair(kPi / 2, kPi / 2)}) {
    cut.remove_geodesic_disk(cut.add_region(true), cut.nearest_vertex(point(u, v)),
                             options.hole_radius);
  }
  cut.clean();
  return cut.finish();
}

HoledSurface make_holed_blob(const BlobSurfaceOptions& options) {
  std::mt19937_64 random(options.seed);
  const std::array<Vec3, 3> rotation = random_rotation(random);
  const int holes = options.holes;
  // Hole centres spread evenly (a Fibonacci lattice), turned by the seed.
  std::vector<Vec3> centres;
  for (int i = 0; i < holes; ++i) {
    const double z = 1 - (2 * i + 1.0) / holes;
    centres.push_back(rotate(rotation, direction(std::acos(z), i * kPi * (3 - std::sqrt(5.0)))));
  }
  std::vector<int> bump_holes;
  const int spacing = std::max(1, holes / std::max(options.bumps, 1));
  for (int k = 0; k < options.bumps; ++k) {
    const int i = k * spacing + 3 + k % 4;
    if (i < holes) bump_holes.push_back(i);
  }
  double phase[3];
  for (double& p : phase) p = 2 * kPi * uniform(random);
  const auto radial_scale = [&](const Vec3& p) {
    double scale = 1 + 0.03 * std::sin(3 * p[0] + phase[0]) * std::sin(2 * p[1] + phase[1]) *
                           std::sin(3 * p[2] + phase[2]);
    for (int i : bump_holes) {
      const double angle = angle_between(p, centres[i]);
      scale += 0.25 * std::exp(-angle * angle / (0.3 * 0.3));
    }
    return scale;
  };
  Mesh blob = icosphere(options.subdivisions);
  for (Vec3& p : blob.positions) p = options.radius * radial_scale(p) * p;
  SurfaceCut cut(std::move(blob));
  for (int i = 0; i < holes; ++i) {
    const int v = cut.nearest_vertex(options.radius * radial_scale(centres[i]) * centres[i]);
    const int kind = i % 10;
    if (kind < 3) {
      cut.remove_fan(cut.add_region(true, false), v, kind + 1);
      continue;
    }
    // A loop of about `target` edges: a disk of that perimeter, less the
    // boundary's zigzag along the edges.
    // Kept within 0.4 of the spacing of the centres, so that holes stay
    // apart on coarse meshes too.
    const int target = 8 + (i * 13) % 53;
    const double apart = std::sqrt(4 * kPi / holes) * options.radius * radial_scale(centres[i]);
    const double radius =
        std::min(target * mean_edge_length_at(cut, v) / (2 * kPi * 1.05), apart / 2.5);
    cut.remove_geodesic_disk(cut.add_region(true), v, radius);
  }
  cut.clean();
  return cut.finish();
}

HoledSurface make_holed_sleeve(const SleeveSurfaceOptions& options) {
  const int around = segments_for(2 * kPi * options.radius, options.edge_length);
  const int rings = segments_for(options.length, options.edge_length) + 1;
  Mesh sleeve;
  for (int j = 0; j < rings; ++j) {
    for (int i = 0; i < around; ++i) {
      const double angle = 2 * kPi * i / around;
      sleeve.positions.push_back({options.radius * std::cos(angle),
                                  options.radius * std::sin(angle),
                                  options.length * j / (rings - 1)});
    }
  }
  // (i, j) -> (angle, z): d angle x dz points outwards.
  sleeve.faces = grid_triangles(around, rings, true, false);
  SurfaceCut cut(std::move(sleeve));
  cut.remove_where(cut.add_region(true), [&](int f) {
    // Developed coordinates about the hole's centre at angle 0, z = length / 2.
    const Vec3 c = centroid(cut.mesh(), cut.mesh().faces[f]);
    const double s = options.radius * std::atan2(c[1], c[0]), z = c[2] - options.length / 2;
    return std::hypot(s / options.hole_half_width, z / options.hole_half_length) < 1;
  });
  cut.clean();
  return cut.finish({0, (rings - 1) * around});
}

namespace {

// A square sheet of side `size` with one fold across it.
DevelopableMesh one_fold_sheet(double size, double edge_length, double amplitude) {
  FoldedSheetOptions sheet;
  sheet.width = sheet.height = size;
  sheet.edge_length = edge_length;
  sheet.amplitude = amplitude;
  sheet.folds = 1;
  return make_folded_sheet(sheet);
}

// The largest flat u of a sheet: its developed width.
double flat_extent(const DevelopableMesh& sheet) {
  double width = 0;
  for (const Vec2& uv : sheet.flat) width = std::max(width, uv[0]);
  return width;
}

}  // namespace

HoledSurface make_sheet_with_long_hole(const SheetSurfaceOptions& options) {
  const DevelopableMesh folded =
      one_fold_sheet(options.size, options.edge_length, options.amplitude);
  const double flat_width = flat_extent(folded);
  SurfaceCut cut(folded.mesh);
  cut.remove_where(cut.add_region(true), [&](int f) {
    double u = 0, v = 0;
    for (int k : folded.mesh.faces[f]) {
      u += folded.flat[k][0] / 3 - flat_width / 6;
      v += folded.flat[k][1] / 3 - options.size / 6;
    }
    return std::hypot(u, v) < options.size * (0.3 + 0.11 * std::cos(9 * std::atan2(v, u)));
  });
  cut.clean();
  return cut.finish({0});
}

HoledSurface make_holed_dome(const DomeSurfaceOptions& options) {
  Mesh sphere = icosphere(options.subdivisions);
  for (Vec3& p : sphere.positions) p = options.radius * p;
  SurfaceCut cut(std::move(sphere));
  const double rim = options.rim_degrees * kPi / 180;
  cut.remove_where(cut.add_region(false), [&](int f) {
    return angle_between(centroid(cut.mesh(), cut.mesh().faces[f]), {0, 0, 1}) > rim;
  });
  const Vec3 centre = direction(options.hole_degrees * kPi / 180, 0);
  cut.remove_where(cut.add_region(true), [&](int f) {
    return angle_between(centroid(cut.mesh(), cut.mesh().faces[f]), centre) < options.hole_radius;
  });
  cut.clean();
  return cut.finish();
}

HoledSurface make_box_with_corner_hole(const BoxSurfaceOptions& options) {
  const int n = options.cells;
  const double s = options.size;
  // Each side: an origin and two axes whose cross product points outwards.
  struct Side {
    Vec3 origin, u, v;
  };
  const Side sides[6] = {{{0, 0, 0}, {0, 0, 1}, {0, 1, 0}}, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},
                         {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}}, {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},
                         {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}}, {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}}};
  Mesh box;
  std::map<std::array<long, 3>, int> welded;  // grid coordinates (0..n) -> vertex
  const auto vertex = [&](const Vec3& grid_point) {
    const std::array<long, 3> key{std::lround(grid_point[0]), std::lround(grid_point[1]),
                                  std::lround(grid_point[2])};
    const auto [it, inserted] = welded.emplace(key, box.vertex_count());
    if (inserted) box.positions.push_back((s / n) * grid_point);
    return it->second;
  };
  const Vec3 corner{double(n), double(n), double(n)};
  for (int side = 0; side < 6; ++side) {
    const Side& f = sides[side];
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        const auto at = [&](int di, int dj) {
          return double(n) * f.origin + double(i + di) * f.u + double(j + dj) * f.v;
        };
        const int a = vertex(at(0, 0)), b = vertex(at(1, 0)), c = vertex(at(1, 1)),
                  d = vertex(at(0, 1));
        // The corner cut out is vertex c of the cell at (n - 1, n - 1) on the
        // sides x = size, y = size and z = size: split through it on x = size
        // only, so that its link has four vertices.
        const bool at_corner = norm(at(1, 1) - corner) < 0.5;
        if (at_corner && side != 1) {
          box.faces.push_back({a, b, d});
          box.faces.push_back({b, c, d});
        } else {
          box.faces.push_back({a, b, c});
          box.faces.push_back({a, c, d});
        }
      }
    }
  }
  SurfaceCut cut(std::move(box));
  const int apex = cut.nearest_vertex((s / n) * corner);
  const std::vector<int> fan = cut.faces_around(apex);
  cut.remove_fan(cut.add_region(true, false), apex, static_cast<int>(fan.size()));
  return cut.finish();
}

HoledSurface make_sheet_with_small_holes(const SmallHolesSurfaceOptions& options) {
  const DevelopableMesh folded =
      one_fold_sheet(options.size, options.edge_length, options.amplitude);
  const double flat_width = flat_extent(folded);
  SurfaceCut cut(folded.mesh);
  for (int count = 1; count <= 3; ++count) {
    const Vec2 target{flat_width * count / 4, options.size / 2};
    int v = 0;
    for (size_t k = 1; k < folded.flat.size(); ++k) {
      const auto d = [&](size_t w) {
        return std::hypot(folded.flat[w][0] - target[0], folded.flat[w][1] - target[1]);
      };
      if (d(k) < d(v)) v = static_cast<int>(k);
    }
    cut.remove_fan(cut.add_region(true, false), v, count);
  }
  return cut.finish({0});
}

HoledSurface make_ruffle_with_c_slot(const RuffleSurfaceOptions& options) {
  // The cone's rulings: unit directions along the curve, tabulated by the
  // parameter t and by the intrinsic angle (arc length on the unit sphere).
  const int table = 1 << 15;
  std::vector<Vec3> ruling(table + 1);
  std::vector<double> angle(table + 1, 0.0);
  for (int k = 0; k <= table; ++k) {
    const double t = 2 * kPi * k / table;
    ruling[k] = normalized({std::cos(t), std::sin(t), options.ruffle * std::sin(3 * t)});
    if (k > 0) angle[k] = angle[k - 1] + 2 * std::asin(norm(ruling[k] - ruling[k - 1]) / 2);
  }
  const double apex_angle = angle.back();
  const auto ruling_at = [&](double intrinsic) {
    const auto it = std::upper_bound(angle.begin(), angle.end(), intrinsic);
    const int k = std::clamp(static_cast<int>(it - angle.begin()) - 1, 0, table - 1);
    const double share = (intrinsic - angle[k]) / (angle[k + 1] - angle[k]);
    return normalized((1 - share) * ruling[k] + share * ruling[k + 1]);
  };

  // Rings at geodesic distances i h from the apex, of about h spacing, each
  // stitched to the next by walking both in step.
  const double h = options.edge_length;
  const int rings = segments_for(options.outer_radius, h);
  Mesh ruffle;
  std::vector<Vec2> polar;  // per vertex: distance from the apex, intrinsic angle
  ruffle.positions.push_back({0, 0, 0});
  polar.push_back({0, 0});
  std::vector<int> inner{0};
  for (int r = 1; r <= rings; ++r) {
    const double rho = options.outer_radius * r / rings;
    const int count = std::max(8, static_cast<int>(std::lround(apex_angle * rho / h)));
    std::vector<int> outer;
    for (int k = 0; k < count; ++k) {
      const double phi = apex_angle * k / count;
      outer.push_back(ruffle.vertex_count());
      ruffle.positions.push_back(rho * ruling_at(phi));
      polar.push_back({rho, phi});
    }
    const int a_count = static_cast<int>(inner.size()), b_count = count;
    for (int a = 0, b = 0; a < a_count || b < b_count;) {
      const bool advance_inner =
          a_count > 1 && a < a_count && (b == b_count || (a + 1.0) / a_count < (b + 1.0) / b_count);
      if (advance_inner) {
        ruffle.faces.push_back({inner[a], outer[b % b_count], inner[(a + 1) % a_count]});
        ++a;
      } else {
        ruffle.faces.push_back({inner[a % a_count], outer[b], outer[(b + 1) % b_count]});
        ++b;
      }
      if (a_count == 1 && b == b_count) break;
    }
    inner = std::move(outer);
  }

  SurfaceCut cut(std::move(ruffle));
  cut.remove_where(cut.add_region(true), [&](int f) {
    const Tri& face = cut.mesh().faces[f];
    double phi[3], rho = 0;
    for (int k = 0; k < 3; ++k) {
      phi[k] = polar[face[k]][1];
      rho += polar[face[k]][0] / 3;
    }
    // A face across angle 0 has corners near 0 and near the apex angle.
    if (*std::max_element(phi, phi + 3) - *std::min_element(phi, phi + 3) > apex_angle / 2) {
      for (double& p : phi) p += p < apex_angle / 2 ? apex_angle : 0;
    }
    const double mean_phi = (phi[0] + phi[1] + phi[2]) / 3;
    return std::abs(rho - options.slot_radius) < options.slot_width / 2 &&
           mean_phi > options.slot_gap / 2 && mean_phi < apex_angle - options.slot_gap / 2;
  });
  cut.clean();
  return cut.finish({inner.front()});
}

}  // namespace foldfill
