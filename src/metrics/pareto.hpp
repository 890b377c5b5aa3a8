#pragma once
// The Pareto front of points with two figures of merit.
#include <cmath>
#include <cstddef>
#include <vector>

namespace millwear {

enum class Better { Higher, Lower };

// True where a point is on the front: no other point is at least as good in both figures
// and better in one. A point with a NaN or infinite figure is never on the front and
// dominates none.
inline std::vector<bool> pareto_front(const std::vector<double>& a, Better a_better, const std::vector<double>& b,
                                      Better b_better) {
  const std::size_t n = a.size();
  const auto better = [](Better way, double x, double y) { return way == Better::Higher ? x > y : x < y; };
  const auto finite = [&](std::size_t i) { return std::isfinite(a[i]) && std::isfinite(b[i]); };
  std::vector<bool> front(n, false);
  for (std::size_t i = 0; i < n; ++i) {
    if (!finite(i)) continue;
    bool dominated = false;
    for (std::size_t j = 0; j < n && !dominated; ++j) {
      if (j == i || !finite(j)) continue;
      const bool no_worse = !better(a_better, a[i], a[j]) && !better(b_better, b[i], b[j]);
      dominated = no_worse && (better(a_better, a[j], a[i]) || better(b_better, b[j], b[i]));
    }
    front[i] = !dominated;
  }
  return front;
}

}  // namespace millwear
