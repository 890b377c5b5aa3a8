#pragma once
// Small helpers shared by the engine, wear and app tests.
#include <string>

#include "scene/scene.hpp"

namespace millwear::testing {

inline std::string source_path(const std::string& rel) {
  return std::string(MILLWEAR_SOURCE_DIR) + "/" + rel;
}

// The lab mill at its own (draft) fidelity: about 200 balls, ~1.5 s per simulated revolution pair.
inline Scene lab_mill() { return load_scene(source_path("scenarios/lab-mill.toml")); }

}  // namespace millwear::testing
