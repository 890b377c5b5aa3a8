#pragma once
// Shared check of the stability suite (tests/stability_*.cpp, docs/stability.md): every
// case either completes with finite state, no escaped disk and bounded energy, or stops
// with an error that names the limit it passed. The runner is in stability_run.hpp.
#include <gtest/gtest.h>

#include <string>

#include "stability_run.hpp"

namespace millwear::stability {

// The invariant of the whole suite. `limit_key` is the scene key a stop must name.
inline void expect_sound_or_clear_stop(const Outcome& o, const std::string& limit_key, const std::string& label) {
  SCOPED_TRACE(label + ": " + describe(o));
  if (!o.completed) {
    EXPECT_NE(o.error.find(limit_key), std::string::npos) << "the stop must name " << limit_key;
    return;
  }
  EXPECT_TRUE(o.finite);
  EXPECT_EQ(o.non_finite, 0);
  EXPECT_EQ(o.escaped, 0);
  EXPECT_LT(o.max_speed_m_s, o.speed_bound_m_s);
}

}  // namespace millwear::stability
