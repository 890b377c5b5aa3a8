#include "geometry/simplify.hpp"

#include <algorithm>

namespace millwear {

namespace {

double segment_distance(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double len2 = length_sq(ab);
  double t = len2 > 0.0 ? dot(p - a, ab) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return length(p - (a + t * ab));
}

// Marks vertices to keep between kept indices i and j (ring indices, j after i, i < j in
// unwrapped order) without recursion depth limits.
void douglas_peucker(const Polygon& ring, int i, int j, double tol, std::vector<char>& keep) {
  const int n = static_cast<int>(ring.size());
  std::vector<std::pair<int, int>> stack{{i, j}};
  while (!stack.empty()) {
    auto [a, b] = stack.back();
    stack.pop_back();
    if (b - a < 2) continue;
    double worst = -1.0;
    int at = -1;
    for (int k = a + 1; k < b; ++k) {
      const double d = segment_distance(ring[k % n], ring[a % n], ring[b % n]);
      if (d > worst) { worst = d; at = k; }
    }
    if (worst > tol) {
      keep[at % n] = 1;
      stack.push_back({a, at});
      stack.push_back({at, b});
    }
  }
}

}  // namespace

std::vector<int> simplify_ring(const Polygon& ring, double tolerance,
                               const std::vector<int>& must_keep) {
  const int n = static_cast<int>(ring.size());
  if (n <= 3) {
    std::vector<int> all(n);
    for (int k = 0; k < n; ++k) all[k] = k;
    return all;
  }
  std::vector<char> keep(n, 0);
  keep[0] = 1;
  // Second anchor: the vertex farthest from vertex 0, so both halves are well posed.
  int far = 1;
  for (int k = 1; k < n; ++k)
    if (length_sq(ring[k] - ring[0]) > length_sq(ring[far] - ring[0])) far = k;
  keep[far] = 1;
  for (int k : must_keep)
    if (k >= 0 && k < n) keep[k] = 1;
  std::vector<int> anchors;
  for (int k = 0; k < n; ++k)
    if (keep[k]) anchors.push_back(k);
  const int m = static_cast<int>(anchors.size());
  for (int a = 0; a < m; ++a) {
    const int i = anchors[a];
    const int j = a + 1 < m ? anchors[a + 1] : anchors[0] + n;
    douglas_peucker(ring, i, j, tolerance, keep);
  }
  std::vector<int> out;
  for (int k = 0; k < n; ++k)
    if (keep[k]) out.push_back(k);
  // A ring needs three vertices.
  for (int k = 0; static_cast<int>(out.size()) < 3 && k < n; ++k)
    if (!keep[k]) { keep[k] = 1; out.clear(); for (int q = 0; q < n; ++q) if (keep[q]) out.push_back(q); }
  return out;
}

}  // namespace millwear
