// Timing shared by the benchmarks.
#pragma once

#include <algorithm>
#include <chrono>
#include <vector>

namespace foldfill::bench {

// Milliseconds of the median of `runs` calls of `work`.
template <class Work>
double median_ms(int runs, const Work& work) {
  std::vector<double> times;
  for (int run = 0; run < runs; ++run) {
    const auto start = std::chrono::steady_clock::now();
    work();
    times.push_back(
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
            .count());
  }
  std::sort(times.begin(), times.end());
  return times[runs / 2];
}

}  // namespace foldfill::bench
