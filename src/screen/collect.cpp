// Collecting a screen: ranking.csv and the figures (see collect.hpp).
#include "screen/collect.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <sstream>

#include "common/errors.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/folder_lock.hpp"
#include "io/run_folder.hpp"
#include "plots/plots.hpp"

namespace millwear::screen {

namespace {

std::vector<std::string> split_words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> w;
  for (std::string x; in >> x;) w.push_back(x);
  return w;
}

// A design's parameter by its designs.csv column name (NaN for a name that is not numeric).
double param_value(const Candidate& c, const std::string& name) {
  if (name == "height_mm") return c.height_mm;
  if (name == "top_width_mm") return c.top_width_mm;
  if (name == "leading_face_angle_deg") return c.leading_deg;
  if (name == "trailing_face_angle_deg") return c.trailing_deg;
  if (name == "rows") return c.rows;
  return std::nan("");
}

}  // namespace

std::string screen_key_path(const std::string& out) { return io::join_path(out, "screen.key"); }

std::string render_screen_figures(const std::string& out, const std::vector<DesignResult>& ranked,
                                  const io::KeyValues& key) {
  if (!plots::gnuplot_available()) return "gnuplot not installed: figures skipped";
  const std::string plots_dir = io::join_path(out, "plots"), data_dir = io::join_path(plots_dir, "data");
  io::ensure_dir(data_dir);
  const std::string log = io::join_path(plots_dir, "gnuplot.log");
  std::string failures;
  auto draw = [&](const std::string& fig, std::map<std::string, std::string> vars) {
    vars["datadir"] = out;
    vars["outbase"] = io::join_path(plots_dir, fig);
    try {
      plots::render_figure(plots::script_path(fig), vars, log);
    } catch (const std::exception& e) {
      failures += (failures.empty() ? "" : "; ") + fig + ": " + e.what();
    }
  };
  std::vector<const DesignResult*> done;
  for (const auto& r : ranked)
    if (r.status == "finished" && std::isfinite(r.life_h)) done.push_back(&r);
  if (done.empty()) return "no finished design with a life: figures skipped";
  draw("screen_pareto", {{"power_sense", io::find_value(key, "power", "min")}});

  // The top three: new and last-stage profiles from each design's run folder.
  std::string blocks, names;
  for (std::size_t i = 0; i < done.size() && i < 3; ++i) {
    const std::string dir = design_dir(out, done[i]->design.name);
    // A design's profiles that do not read (another process rewriting its folder) leave it
    // out of this figure, which says so: the ranking stands.
    try {
      const std::vector<int> st = io::list_finished_stages(dir, done[i]->design.name);
      if (st.empty()) continue;
      std::string design_blocks;
      for (int k : {0, st.back()}) {
        const io::CsvData p = io::read_csv(io::profile_path(dir, done[i]->design.name, k));
        for (std::size_t r = 0; r < p.row_count(); ++r)
          design_blocks += io::format_number(p.number(r, "x_mm")) + "," + io::format_number(p.number(r, "y_mm")) + "\n";
        design_blocks += "\n\n";
      }
      blocks += design_blocks;
      names += (names.empty() ? "" : " ") + done[i]->design.name;
    } catch (const std::exception& e) {
      failures += (failures.empty() ? "" : "; ") + std::string("screen_top_profiles: ") + e.what();
    }
  }
  io::write_file_atomic(io::join_path(data_dir, "top_profiles.dat"), blocks);
  draw("screen_top_profiles", {{"designs", names}});

  // Heat map for a family with exactly two numeric parameters.
  const std::vector<std::string> varying = split_words(io::find_value(key, "varying"));
  if (varying.size() == 2 && std::isfinite(param_value(Candidate{}, varying[0])) &&
      std::isfinite(param_value(Candidate{}, varying[1]))) {
    std::string rows;
    for (const DesignResult* r : done)
      rows += io::format_number(param_value(r->design, varying[0])) + "," +
              io::format_number(param_value(r->design, varying[1])) + "," + io::format_number(r->life_h) + "," +
              r->design.name + "\n";
    io::write_file_atomic(io::join_path(data_dir, "heatmap.dat"), rows);
    draw("screen_heatmap", {{"xlabel_text", varying[0]}, {"ylabel_text", varying[1]}});
  }
  return failures;
}

CollectOutcome collect_screen(const std::string& out, bool take_lock) {
  std::error_code ec;
  std::optional<io::FolderLock> lock;
  if (take_lock && std::filesystem::is_directory(out, ec)) lock.emplace(out);
  if (!io::file_exists(designs_csv(out)))
    throw InputError(out, "--collect", "a screen output folder (no designs.csv in it)");
  const std::string key_file = screen_key_path(out);
  const io::KeyValues key = io::file_exists(key_file) ? io::read_key_values(key_file) : io::KeyValues{};
  const std::vector<Candidate> designs = read_designs(out);
  // A screen writes every valid candidate and refuses a family with none: no design is a
  // damaged list, not a screen to rank (over the ranking already there).
  if (designs.empty())
    throw InputError(designs_csv(out), "line 2", "at least one design (a screen writes every valid candidate)");
  std::vector<DesignResult> results;
  for (const auto& c : designs) results.push_back(read_design_result(out, c));
  CollectOutcome o;
  o.ranked = rank_designs(results, io::find_value(key, "power") == "max");
  write_ranking(out, o.ranked);
  o.figure_error = render_screen_figures(out, o.ranked, key);
  // Skipped (no gnuplot, or no design to draw) is not failed.
  const bool any_drawn = std::any_of(o.ranked.begin(), o.ranked.end(), [](const DesignResult& r) {
    return r.status == "finished" && std::isfinite(r.life_h);
  });
  o.figures_failed = !o.figure_error.empty() && plots::gnuplot_available() && any_drawn;
  for (const auto& r : o.ranked) o.figures_failed = o.figures_failed || !r.figure_error.empty();
  for (const auto& r : o.ranked) {
    if (r.status == "failed") ++o.failed;
    else if (r.status == "missing") ++o.missing;
  }
  return o;
}

}  // namespace millwear::screen
