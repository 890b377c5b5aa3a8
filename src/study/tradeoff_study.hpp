#pragma once
// `millwear tradeoff` as library calls: the designs of a scene or comparison file over the
// fidelity ladder (tradeoff.hpp), and the files of the report.
//
//   OUT/tradeoff.csv          one row per setting: costs (summed over the designs), errors
//                             (the worst design), comparison order, Pareto flag
//   OUT/tradeoff_designs.csv  one row per setting and design: final area, height, life,
//                             its own profile and life errors
//   OUT/tradeoff_front.csv    the Pareto-front rows by CPU time (the figure's front line)
//   OUT/tradeoff_profiles.csv final unit surface of every setting (label, design, x_mm, y_mm)
//   OUT/tradeoff.md           the table as Markdown, with the run's settings
//   OUT/tradeoff.png, .svg    error against CPU time (plots/tradeoff.gp), front marked
#include <functional>
#include <string>
#include <vector>

#include "study/tradeoff.hpp"

namespace millwear {

struct TradeoffStudyRequest {
  std::string scene_file;   // one design, or a comparison file
  std::vector<std::string> overrides;  // --set KEY=VALUE, on every design (scene/scene.hpp)
  std::string out;
  TradeoffOptions options;
  int jobs = 1;
  bool figure = true;       // draw OUT/tradeoff.png and .svg
  std::string commit;       // the program's, for OUT/manifest.json
};

struct TradeoffStudyCallbacks {
  std::function<void(const TradeoffLadder&)> on_ladder;  // once the ladder is built, before any run
  TradeoffCallbacks runs;
};

struct TradeoffStudy {
  TradeoffReport report;
  std::vector<std::string> figure_files;  // empty without the figure
  std::string figure_error;               // the figure failed (RunError text); the tables are written
  bool figure_skipped = false;            // one setting: nothing to trade off, no figure drawn
};

// Loads and checks the designs (InputError before anything is written), builds the ladder,
// creates and locks OUT (io/folder_lock.hpp) for the whole study, runs the ladder
// (run_tradeoff) and writes the files above into OUT's staging folder, moved into OUT once all
// are written (io/staging.hpp): a ladder that fails or is stopped leaves an earlier one's files
// as they were.
TradeoffStudy run_tradeoff_study(const TradeoffStudyRequest& request, const TradeoffStudyCallbacks& callbacks = {});

// The CSV and Markdown files of a report in `out` (an existing folder), atomically.
void write_tradeoff_files(const TradeoffReport& report, const std::string& out);

// OUT/tradeoff.png and .svg from the files in OUT (gnuplot's messages in OUT/gnuplot.log).
// Returns the files; throws RunError when the figure fails.
std::vector<std::string> render_tradeoff_figure(const std::string& out);

}  // namespace millwear
