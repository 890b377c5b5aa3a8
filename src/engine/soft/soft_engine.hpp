#pragma once
// Our own disk solver, derived from Box2D v3's soft step and specialised to a mill slice:
// thousands of disks, one rotating liner, nothing else. See soft_engine.cpp for the step.
#include <memory>

#include "engine/engine.hpp"

namespace millwear {

std::unique_ptr<Engine> make_soft_engine(const Scene& scene, const MillGeometry& mill,
                                         const ChargeState& initial,
                                         const AccountingOptions& opts);

}  // namespace millwear
