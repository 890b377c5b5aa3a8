// `millwear tradeoff` as library calls (see tradeoff_study.hpp). Lengths and areas are SI in
// the report and converted to mm and mm^2 here, where they are written.
#include "study/tradeoff_study.hpp"

#include <algorithm>
#include <sstream>

#include "common/errors.hpp"
#include "common/units.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/folder_lock.hpp"
#include "io/run_folder.hpp"
#include "io/staging.hpp"
#include "plots/plots.hpp"
#include "study/command_manifest.hpp"
#include "study/plan.hpp"

namespace millwear {

namespace {

std::string fmt(double v, const char* f = "%.2f") { return io::format_for_table(v, f); }

std::string markdown(const TradeoffReport& r) {
  const bool several = r.design_names.size() > 1;
  std::ostringstream md;
  md << "Scene `" << r.scene_name << "`, " << r.stages << " stage(s) of " << r.stage_hours << " h; new lifter";
  for (std::size_t k = 0; k < r.design_names.size(); ++k)
    md << (k ? "," : "") << " " << (several ? r.design_names[k] + " " : "") << fmt(in_mm(r.lifter_height_m[k]), "%.1f")
       << " mm high, " << fmt(in_mm2(r.lifter_area_m2[k]), "%.0f") << " mm^2";
  md << ". Errors against `reference`" << (several ? ", the worst design; CPU and wall time summed over the designs" : "")
     << ".\n\n";
  md << "| setting | CPU (s) | wall (s) | speed-up | profile dev. max (mm / % h) | mean (mm / % h) | area err (% A0) "
        "| power err (%) | life (h) | life err (%) | "
     << (several ? "order same | life ratio err (%) | " : "") << "events | front |\n";
  md << "|---|---|---|---|---|---|---|---|---|---|" << (several ? "---|---|" : "") << "---|---|\n";
  for (const auto& row : r.rows) {
    std::string lives;
    for (const auto& d : row.designs)
      lives += (lives.empty() ? "" : " / ") + fmt(d.life_h, "%.0f") + (d.life_extrapolated ? "*" : "");
    md << "| " << row.label << " | " << fmt(row.cpu_s, "%.0f") << " | " << fmt(row.wall_s, "%.0f") << " | "
       << fmt(row.speedup, "%.1f") << "x | " << fmt(in_mm(row.dev_max_m), "%.1f") << " / "
       << fmt(row.dev_max_pct, "%.1f") << " | " << fmt(in_mm(row.dev_mean_m), "%.1f") << " / "
       << fmt(row.dev_mean_pct, "%.1f") << " | " << fmt(row.area_err_pct) << " | " << fmt(row.power_err_pct, "%.1f")
       << " | " << lives << " | " << fmt(row.life_err_pct, "%.1f") << " | ";
    if (several)
      md << (row.error.empty() ? (row.life_order_same ? "yes" : "NO") : "-") << " | "
         << fmt(row.life_ratio_err_pct, "%.1f") << " | ";
    md << (row.error.empty() ? std::to_string(row.events.size()) : "failed") << " | " << (row.pareto ? "yes" : "")
       << " |\n";
  }
  md << "\nSpeed-up: reference CPU time / CPU time. * life extrapolated beyond the simulated stages.";
  if (several)
    md << " Life is listed per design (" << r.scene_name << "); order same: the designs come out in the "
       << "reference's order of life; life ratio err: error of each design's life relative to the first's.";
  md << "\n";
  for (const auto& row : r.rows)
    if (row.knob == "seed" && row.label.rfind("reference", 0) == 0 && row.error.empty())
      md << "\nNoise floor: `" << row.label << "` (the reference's numerics, the charge's noise drawn again) "
         << "deviates " << fmt(row.dev_max_pct, "%.1f") << "% of the lifter height at the worst point and "
         << fmt(row.dev_mean_pct, "%.1f") << "% on average, area " << fmt(row.area_err_pct)
         << "%, life " << fmt(row.life_err_pct, "%.1f")
         << "%: a setting closer to the reference than that cannot be told from it.\n";
  for (const auto& h : r.held_knobs) md << "\nHeld: " << h;
  if (!r.held_knobs.empty()) md << "\n";
  return md.str();
}

}  // namespace

void write_tradeoff_files(const TradeoffReport& r, const std::string& out) {
  io::CsvTable t({"label", "knob", "value", "wall_s", "cpu_s", "speedup", "disk_steps", "simulated_s", "dev_max_mm",
                  "dev_max_pct", "dev_mean_mm", "dev_mean_pct", "area_err_pct", "power_err_pct", "life_err_pct",
                  "life_order_same", "life_ratio_err_pct", "events", "error", "pareto"});
  io::CsvTable per({"label", "design", "final_hours", "final_area_mm2", "final_height_mm", "life_h",
                    "life_extrapolated", "dev_max_pct", "life_err_pct"});
  io::CsvTable front({"label", "cpu_s", "wall_s", "dev_max_pct", "dev_mean_pct"});
  io::CsvTable prof({"label", "design", "x_mm", "y_mm"});
  std::vector<const TradeoffRow*> on_front;
  for (const auto& row : r.rows) {
    t.add_row({row.label, row.knob, row.value, row.wall_s, row.cpu_s, row.speedup, static_cast<long long>(row.disk_steps),
               row.simulated_s, in_mm(row.dev_max_m), row.dev_max_pct, in_mm(row.dev_mean_m), row.dev_mean_pct,
               row.area_err_pct, row.power_err_pct, row.life_err_pct, row.life_order_same, row.life_ratio_err_pct,
               static_cast<long long>(row.events.size()), row.error, row.pareto});
    if (row.pareto) on_front.push_back(&row);
    for (const auto& d : row.designs) {
      per.add_row({row.label, d.name, d.final_hours, in_mm2(d.final_area_m2), in_mm(d.final_height_m), d.life_h,
                   d.life_extrapolated, d.dev_max_pct, d.life_err_pct});
      for (const Vec2& p : d.final_profile) prof.add_row({row.label, d.name, in_mm(p.x), in_mm(p.y)});
    }
  }
  std::sort(on_front.begin(), on_front.end(), [](auto* a, auto* b) { return a->cpu_s < b->cpu_s; });
  for (const auto* row : on_front)
    front.add_row({row->label, row->cpu_s, row->wall_s, row->dev_max_pct, row->dev_mean_pct});
  t.write(out + "/tradeoff.csv");
  per.write(out + "/tradeoff_designs.csv");
  front.write(out + "/tradeoff_front.csv");
  prof.write(out + "/tradeoff_profiles.csv");
  io::write_file_atomic(out + "/tradeoff.md", markdown(r));
}

TradeoffStudy run_tradeoff_study(const TradeoffStudyRequest& request, const TradeoffStudyCallbacks& cb) {
  // A scene or a comparison file; InputError before anything is written.
  const std::vector<Scene> designs = study::load_designs(request.scene_file, request.overrides);
  const TradeoffLadder ladder = tradeoff_ladder(designs, request.options);
  const io::FolderLock lock(request.out, "tradeoff");  // one writer per folder, for the whole run
  io::check_output_names(request.out, {"manifest.json", "tradeoff.csv", "tradeoff_designs.csv", "tradeoff_front.csv",
                                       "tradeoff_profiles.csv", "tradeoff.md", "tradeoff.png", "tradeoff.svg",
                                       "gnuplot.log"}, "tradeoff");
  // The new files are drawn up beside an earlier ladder's, which stay in OUT as they were until
  // every new file is complete (a ladder whose reference fails, or one stopped, leaves them).
  io::StagedOutputs staged(request.out);
  const std::string& out = staged.dir();
  if (cb.on_ladder) cb.on_ladder(ladder);
  TradeoffStudy study;
  study.report = run_tradeoff(ladder, request.jobs, cb.runs);
  write_tradeoff_files(study.report, out);
  // One setting (--only reference) has nothing to trade off: a figure of one point is none.
  study.figure_skipped = request.figure && study.report.rows.size() < 2;
  if (request.figure && !study.figure_skipped) {
    try {
      study.figure_files = render_tradeoff_figure(out);
    } catch (const RunError& e) {
      study.figure_error = staged.in_out_text(e.what());
    }
  }
  const TradeoffOptions& o = request.options;
  std::string only;
  for (const std::string& label : o.only) only += (only.empty() ? "" : ",") + label;
  // Every setting runs its own preset: the record names none. The designs of a comparison
  // may each have their own seed: then each is named.
  study::CommandRecord record{"tradeoff", request.commit, request.scene_file, request.overrides, "", {}, {}, {}};
  std::string seeds;
  bool one_seed = true;
  for (const Scene& d : designs) {
    seeds += (seeds.empty() ? "" : " ") + d.name + "=" + std::to_string(d.solver.seed);
    one_seed = one_seed && d.solver.seed == designs.front().solver.seed;
  }
  if (one_seed) record.seed = designs.front().solver.seed;
  else record.settings.emplace_back("seeds", seeds);
  record.settings.emplace_back("quick", o.quick ? "true" : "false");
  record.settings.emplace_back("stages", o.stages > 0 ? std::to_string(o.stages) : "the scene's");
  record.settings.emplace_back("stage_hours", o.stage_hours > 0.0 ? io::format_number(o.stage_hours) : "the scene's");
  record.settings.emplace_back("only", only);
  record.files = {"tradeoff.csv", "tradeoff_designs.csv", "tradeoff_front.csv", "tradeoff_profiles.csv",
                  "tradeoff.md"};
  record.files.insert(record.files.end(), study.figure_files.begin(), study.figure_files.end());
  record.files.push_back(io::join_path(out, "gnuplot.log"));
  study::write_command_manifest(out, record);
  staged.commit({request.scene_file});
  for (std::string& f : study.figure_files) f = staged.in_out(f);
  return study;
}

std::vector<std::string> render_tradeoff_figure(const std::string& out) {
  return plots::render_figure(plots::script_path("tradeoff"), {{"datadir", out}, {"outbase", out + "/tradeoff"}},
                              out + "/gnuplot.log");
}

}  // namespace millwear
