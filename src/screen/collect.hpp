#pragma once
// Collecting a screen (`millwear screen --collect OUT`, and the end of a local screen):
// every design's result read from its folder, ranked (ranking.hpp), OUT/ranking.csv written
// and the figures drawn from whatever finished.
//
// Figures in OUT/plots (PNG and SVG, data in OUT/plots/data): screen_pareto (life against
// power and utilisation), screen_top_profiles (new and last-stage profiles of the three
// longest lives: top_profiles.dat) and, for a family with exactly two numeric parameters,
// screen_heatmap (life over the two: heatmap.dat).
#include <string>
#include <vector>

#include "io/run_folder.hpp"
#include "screen/ranking.hpp"

namespace millwear::screen {

struct CollectOutcome {
  std::vector<DesignResult> ranked;   // ranking order (rank_designs)
  int failed = 0, missing = 0;
  std::string figure_error;           // "" when every figure was drawn
  bool figures_failed = false;        // a figure failed with gnuplot installed (exit 1, as run's)
};

// Takes OUT's lock (io/folder_lock.hpp; one writer of the ranking and figures at a time)
// unless the caller holds it. Throws InputError when OUT holds no screen (no designs.csv)
// or another process holds the lock.
CollectOutcome collect_screen(const std::string& out, bool take_lock = true);

// The figures above from the ranked designs; `key` is OUT/screen.key (power sense, the
// varying parameters). Returns the failures as text ("" when all drawn).
std::string render_screen_figures(const std::string& out, const std::vector<DesignResult>& ranked,
                                  const io::KeyValues& key);

// OUT/screen.key: the screen's fingerprint, name, power sense and varying parameters.
std::string screen_key_path(const std::string& out);

}  // namespace millwear::screen
