#pragma once
// The edges of a polyline in a binary tree of bounding boxes over their order along the line:
// the edges near a segment are found in about log n box tests instead of n. Used by the
// crossing tests, which a measured profile of a million points would otherwise make take
// hours.
#include <cstddef>
#include <vector>

#include "geometry/polyline.hpp"

namespace millwear {

// An axis-aligned box, closed: boxes that share only an edge or a corner meet.
struct Box2 {
  double x0, y0, x1, y1;
};

inline Box2 box_of(Vec2 a, Vec2 b) {
  return {a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.x < b.x ? b.x : a.x,
          a.y < b.y ? b.y : a.y};
}

inline bool boxes_meet(const Box2& a, const Box2& b) {
  return a.x0 <= b.x1 && b.x0 <= a.x1 && a.y0 <= b.y1 && b.y0 <= a.y1;
}

class EdgeTree {
 public:
  static constexpr std::size_t kNone = static_cast<std::size_t>(-1);

  // Edge j runs from line[j] to line[j + 1]; each edge's box is grown by `margin` on every side.
  EdgeTree(const Polyline& line, double margin);

  std::size_t edge_count() const { return edges_; }

  // The last edge j in [first, last] whose box meets `query` and for which hit(j) is true;
  // kNone if there is none. Edges are visited from the back, and only where boxes meet.
  template <class Hit>
  std::size_t last_hit(const Box2& query, std::size_t first, std::size_t last, Hit&& hit) const {
    if (edges_ == 0 || first > last || first >= edges_) return kNone;
    struct Node {
      std::size_t id, lo, hi;  // covers edges [lo, hi)
    };
    Node stack[2 * 64];
    int top = 0;
    stack[top++] = {1, 0, leaves_};
    while (top > 0) {
      const Node v = stack[--top];
      if (v.hi <= first || v.lo > last || !boxes_meet(box_[v.id], query)) continue;
      if (v.hi - v.lo == 1) {
        if (hit(v.lo)) return v.lo;
        continue;
      }
      const std::size_t mid = v.lo + (v.hi - v.lo) / 2;
      stack[top++] = {2 * v.id, v.lo, mid};       // the left half after the right
      stack[top++] = {2 * v.id + 1, mid, v.hi};
    }
    return kNone;
  }

 private:
  std::size_t edges_ = 0;
  std::size_t leaves_ = 1;  // a power of two, at least edges_
  std::vector<Box2> box_;   // node 1 the root, node k's children 2k and 2k + 1
};

}  // namespace millwear
