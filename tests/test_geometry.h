// Small geometry shared by the tests: 2D areas, a small folded sheet and a
// mesh whose hole cannot lie flat.
#pragma once

#include <cmath>
#include <vector>

#include "foldfill/examples.h"
#include "foldfill/mesh.h"

namespace foldfill::testing {

inline double twice_signed_area(const Vec2& a, const Vec2& b, const Vec2& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

inline double polygon_area(const std::vector<Vec2>& polygon) {
  double twice = 0;
  for (size_t k = 0; k < polygon.size(); ++k) {
    const Vec2& a = polygon[k];
    const Vec2& b = polygon[(k + 1) % polygon.size()];
    twice += a[0] * b[1] - a[1] * b[0];
  }
  return twice / 2;
}

// A 3 x 2 sheet with two folds of amplitude 0.2 (exactly developable).
inline DevelopableMesh small_folded_sheet(double edge_length) {
  FoldedSheetOptions options;
  options.width = 3;
  options.height = 2;
  options.edge_length = edge_length;
  options.amplitude = 0.2;
  options.folds = 2;
  return make_folded_sheet(options);
}

// A collar of `segments` quads whose inner ring (vertices [0, segments))
// ripples up and down, far longer than the outer ring: no flat annulus has
// such a hole, so its flattening crosses itself.
inline Mesh rippled_collar(int segments = 48) {
  Mesh collar;
  for (int ring = 0; ring < 2; ++ring)
    for (int k = 0; k < segments; ++k) {
      const double angle = 2 * M_PI * k / segments, radius = ring == 0 ? 1.0 : 1.3;
      const double height = ring == 0 ? 0.6 * std::sin(8 * angle) : 0;
      collar.positions.push_back({radius * std::cos(angle), radius * std::sin(angle), height});
    }
  for (int k = 0; k < segments; ++k) {
    const int a = k, b = (k + 1) % segments, c = segments + b, d = segments + a;
    collar.faces.push_back({a, d, c});
    collar.faces.push_back({a, c, b});
  }
  return collar;
}

}  // namespace foldfill::testing
