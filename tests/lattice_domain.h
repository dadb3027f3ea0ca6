// A hand-built EmbedDomain for the embedding tests (ARAP, solver): a lattice
// of equilateral triangles whose two outer rings are the fixed strip; and a
// flat layer of cloth over it for the contact tests.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <vector>

#include "foldfill/contact.h"
#include "foldfill/domain.h"

namespace foldfill::testing {

// A (columns x rows) lattice of equilateral triangles with unit edges. Ring 0
// (the outer rectangle of lattice indices) is the strip's one-ring, ring 1 the
// hole loop; they are fixed at `place(uv)`; the rest is free.
inline EmbedDomain lattice_domain(int columns, int rows,
                                  const std::function<Vec3(const Vec2&)>& place) {
  const double row_height = std::sqrt(3.0) / 2;
  auto id = [&](int i, int j) { return j * columns + i; };
  auto ring = [&](int i, int j) {
    return std::min(std::min(i, columns - 1 - i), std::min(j, rows - 1 - j));
  };
  // New order: the loop (ring 1, walked counter-clockwise), ring 0, the rest.
  std::vector<int> order;
  for (int i = 1; i < columns - 1; ++i) order.push_back(id(i, 1));
  for (int j = 2; j < rows - 1; ++j) order.push_back(id(columns - 2, j));
  for (int i = columns - 3; i >= 1; --i) order.push_back(id(i, rows - 2));
  for (int j = rows - 3; j >= 2; --j) order.push_back(id(1, j));
  const int loop_size = static_cast<int>(order.size());
  for (bool outer : {true, false})
    for (int j = 0; j < rows; ++j)
      for (int i = 0; i < columns; ++i)
        if (outer ? ring(i, j) == 0 : ring(i, j) >= 2) order.push_back(id(i, j));
  std::vector<int> new_index(order.size());
  for (size_t k = 0; k < order.size(); ++k) new_index[order[k]] = static_cast<int>(k);

  EmbedDomain domain;
  domain.loop_size = loop_size;
  domain.fixed_count = loop_size + 2 * (columns + rows) - 4;
  domain.rest_uv.resize(order.size());
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < columns; ++i)
      domain.rest_uv[new_index[id(i, j)]] = {i + 0.5 * (j % 2), j * row_height};
  for (int k = 0; k < domain.fixed_count; ++k)
    domain.fixed_positions.push_back(place(domain.rest_uv[k]));

  std::vector<Tri> strip_faces, patch_faces;
  for (int j = 0; j + 1 < rows; ++j) {
    for (int i = 0; i + 1 < columns; ++i) {
      const std::array<Tri, 2> pair =
          j % 2 == 0 ? std::array<Tri, 2>{Tri{id(i, j), id(i + 1, j), id(i, j + 1)},
                                          Tri{id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)}}
                     : std::array<Tri, 2>{Tri{id(i, j), id(i + 1, j + 1), id(i, j + 1)},
                                          Tri{id(i, j), id(i + 1, j), id(i + 1, j + 1)}};
      for (const Tri& f : pair) {
        const bool on_strip = ring(f[0] % columns, f[0] / columns) == 0 ||
                              ring(f[1] % columns, f[1] / columns) == 0 ||
                              ring(f[2] % columns, f[2] / columns) == 0;
        const Tri renumbered{new_index[f[0]], new_index[f[1]], new_index[f[2]]};
        (on_strip ? strip_faces : patch_faces).push_back(renumbered);
      }
    }
  }
  domain.strip_face_count = static_cast<int>(strip_faces.size());
  domain.faces = strip_faces;
  domain.faces.insert(domain.faces.end(), patch_faces.begin(), patch_faces.end());
  return domain;
}

// A flat square layer of cloth at height z (normalised units) over `domain`'s
// strip and one unit beyond it, an n x n grid of squares, each split into two
// triangles.
inline PatchScene flat_layer(const EmbedDomain& domain, double z, int n) {
  double low[2] = {1e9, 1e9}, high[2] = {-1e9, -1e9};
  for (const Vec3& p : domain.fixed_positions)
    for (int c = 0; c < 2; ++c) {
      low[c] = std::min(low[c], p[c] - 1);
      high[c] = std::max(high[c], p[c] + 1);
    }
  PatchScene scene;
  const int first = domain.fixed_count;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      scene.positions.push_back(
          {low[0] + (high[0] - low[0]) * i / n, low[1] + (high[1] - low[1]) * j / n, z});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = first + j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      scene.faces.push_back({a, b, c});
      scene.faces.push_back({a, c, d});
    }
  return scene;
}

}  // namespace foldfill::testing
