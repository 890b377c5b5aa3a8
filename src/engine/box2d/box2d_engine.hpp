#pragma once
// The Box2D 2.4 library backend. Box2D types stay inside engine/box2d/.
#include <memory>

#include "engine/engine.hpp"

namespace millwear {

std::unique_ptr<Engine> make_box2d_engine(const Scene& scene, const MillGeometry& mill,
                                          const ChargeState& initial,
                                          const AccountingOptions& opts);

}  // namespace millwear
