#include "geometry/edge_tree.hpp"

#include <algorithm>
#include <limits>

namespace millwear {

EdgeTree::EdgeTree(const Polyline& line, double margin) {
  edges_ = line.size() < 2 ? 0 : line.size() - 1;
  while (leaves_ < edges_) leaves_ *= 2;
  constexpr double kInf = std::numeric_limits<double>::infinity();
  box_.assign(2 * leaves_, Box2{kInf, kInf, -kInf, -kInf});  // an empty box meets nothing
  for (std::size_t j = 0; j < edges_; ++j) {
    Box2 b = box_of(line[j], line[j + 1]);
    b.x0 -= margin;
    b.y0 -= margin;
    b.x1 += margin;
    b.y1 += margin;
    box_[leaves_ + j] = b;
  }
  for (std::size_t k = leaves_ - 1; k >= 1; --k) {
    const Box2& l = box_[2 * k];
    const Box2& r = box_[2 * k + 1];
    box_[k] = {std::min(l.x0, r.x0), std::min(l.y0, r.y0), std::max(l.x1, r.x1),
               std::max(l.y1, r.y1)};
  }
}

}  // namespace millwear
