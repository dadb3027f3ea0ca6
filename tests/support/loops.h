// The lookup of a boundary loop by one of its vertices, which the tests and
// the benchmarks share.
#pragma once

#include <algorithm>
#include <vector>

#include "foldfill/holes.h"

namespace foldfill::testing {

// The id of the loop through `vertex`, or -1 when no loop passes through it.
inline int loop_through(const std::vector<BoundaryLoop>& loops, int vertex) {
  for (const BoundaryLoop& loop : loops) {
    if (std::find(loop.vertices.begin(), loop.vertices.end(), vertex) != loop.vertices.end())
      return loop.id;
  }
  return -1;
}

}  // namespace foldfill::testing
