#pragma once
// Douglas-Peucker simplification of a closed ring, by index: the contact solver collides
// against a coarse copy of the liner (few, long edges: cheap broad phase) while the wear
// accounting keeps the fine edges.
#include <vector>

#include "geometry/polyline.hpp"

namespace millwear {

// Indices (increasing) of the ring's vertices to keep so that no dropped vertex lies
// farther than tolerance from the kept chain. Always keeps at least 3 vertices; vertices
// in must_keep (sorted or not) are kept too.
std::vector<int> simplify_ring(const Polygon& ring, double tolerance,
                               const std::vector<int>& must_keep = {});

}  // namespace millwear
