// Running the designs of a plan: threads, resume, the stage files and the tables.
#include "study/run_designs.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <optional>
#include <set>
#include <stdexcept>
#include <thread>

#include <nlohmann/json.hpp>

#include "common/errors.hpp"
#include "common/parallel.hpp"
#include "io/atomic_write.hpp"
#include "io/folder_lock.hpp"
#include "io/run_folder.hpp"
#include "plots/plots.hpp"
#include "study/design_estimates.hpp"
#include "study/run_outputs.hpp"
#include "study/stage_files.hpp"
#include "study/vtk_output.hpp"
#include "wear/life.hpp"

namespace millwear::study {

namespace fs = std::filesystem;

const char* status_name(DesignStatus s) {
  switch (s) {
    case DesignStatus::Waiting: return "waiting";
    case DesignStatus::Running: return "running";
    case DesignStatus::Done: return "finished";
    case DesignStatus::Failed: return "failed";
    case DesignStatus::Interrupted: return "interrupted";
  }
  return "?";
}

namespace {

// Thrown from on_stage by stop_after_stage; the wear loop passes it through.
struct StopRequested : std::runtime_error {
  StopRequested() : std::runtime_error("stopped after the requested stage (--stop-after-stage)") {}
};

bool stop_requested(const RunOptions& opt) { return opt.stop_signal && opt.stop_signal->load() != 0; }

void tick(const RunOptions& opt) {
  if (opt.on_tick) opt.on_tick();
}

// What the run keeps of a stage for the tables and the progress (DesignState::stages):
// no charge states, no edge rates, no frames.
StageRecord light_copy(const StageRecord& rec) {
  StageRecord light = rec;
  light.frames.clear();
  light.edge_shear_W_per_m2.clear();
  light.edge_impact_W_per_m2.clear();
  light.snapshot = ChargeState{};
  light.start_charge = ChargeState{};
  light.edge_wear_rate_m_per_s.clear();
  return light;
}
}  // namespace

// Life from the stages so far (final histories carry their own).

void life_of(const DesignInput& d, const DesignState& st, double& life_h, bool& extrapolated) {
  if (st.have_history) {
    life_h = st.life_h;
    extrapolated = st.life_extrapolated;
    return;
  }
  life_h = std::nan("");
  extrapolated = true;
  if (st.stages.size() < 2) return;
  WearHistory h;
  for (const auto& [k, r] : st.stages) h.stages.push_back(r);
  try {
    compute_life(h, d.scene.wear.replacement_height_m);
    life_h = h.life_h;
    extrapolated = h.life_extrapolated;
  } catch (const std::exception&) {
  }
}

// A pattern's life of each kind of lifter (empty for a plain liner).
void kind_lives_of(const DesignInput& d, const DesignState& st, std::vector<double>& life_h,
                   std::vector<bool>& extrapolated) {
  life_h.clear();
  extrapolated.clear();
  if (d.scene.mill.kind_count() < 2 || st.stages.empty()) return;
  WearHistory h;
  for (const auto& [k, rec] : st.stages) h.stages.push_back(rec);
  compute_life(h, d.scene.wear.replacement_height_m);
  life_h = h.kind_life_h;
  extrapolated = h.kind_life_extrapolated;
}

namespace {

// Books a file as written by this run (for the manifest's list). Caller holds the mutex.
void note(RunState& ctx, const std::string& out, const std::string& path) {
  const std::string rel = io::relative_to(out, path);
  if (!rel.empty()) ctx.written.insert(rel);
}

}  // namespace

RunEstimates run_estimates(const RunState& state) {
  RunEstimates e;
  const Plan& plan = state.plan;
  for (std::size_t i = 0; i < plan.designs.size(); ++i) {
    const DesignInput& d = plan.designs[i];
    double life_h = std::nan("");
    bool extrapolated = true;
    life_of(d, *state.designs[i], life_h, extrapolated);
    std::vector<double> kind_life_h;
    std::vector<bool> kind_extrapolated;
    kind_lives_of(d, *state.designs[i], kind_life_h, kind_extrapolated);
    e.histories.push_back(estimate_history(d.name, d.scene, state.designs[i]->stages, life_h, extrapolated,
                                           kind_life_h, kind_extrapolated));
  }
  for (const std::string& name : design_names(plan)) {
    std::vector<DesignEstimate> histories;
    for (std::size_t i = 0; i < plan.designs.size(); ++i)
      if (plan.designs[i].design == name) histories.push_back(e.histories[i]);
    e.designs.push_back(histories.size() == 1 ? histories.front() : combine_histories(name, histories));
  }
  e.verdicts = compare_designs(e.designs, plan.reference);
  return e;
}

namespace {

// The run's plain report for the table writers. Caller holds the mutex.
study::RunReport report_of(const RunState& ctx, const RunOptions& opt, bool final_write) {
  study::RunReport r;
  r.out = opt.out;
  r.program_version = MILLWEAR_VERSION;
  r.program_commit = opt.commit;
  r.started = ctx.started_text;
  r.finished = final_write;
  r.wall_s = std::chrono::duration<double>(Clock::now() - ctx.t0).count();
  r.fidelity = ctx.plan.fidelity;
  r.reference = ctx.plan.reference;
  r.resumed = opt.resume;
  r.jobs = ctx.jobs;
  r.comparison_files = ctx.plan.comparison_files;
  for (std::size_t i = 0; i < ctx.plan.designs.size(); ++i) {
    const DesignInput& d = ctx.plan.designs[i];
    const DesignState& st = *ctx.designs[i];
    study::DesignReport dr;
    dr.name = d.name;
    dr.design = d.design;
    dr.replicate = d.replicate;
    dr.scene = &d.scene;
    dr.input_files = d.files;
    auto copies = ctx.copied.find(d.name);
    if (copies != ctx.copied.end()) dr.input_copies = copies->second;
    dr.status = status_name(st.status);
    dr.error = st.error;
    dr.resumed_stages = st.resumed_up_to + 1;
    life_of(d, st, dr.life_h, dr.life_extrapolated);
    dr.wear_rate_m3_per_J = st.wear_rate_m3_per_J;
    dr.stages = st.stages;
    dr.events = st.events;
    dr.continue_run = d.continue_run;
    dr.continue_stage = d.continue_stage;
    dr.continue_hours = d.continue_hours;
    dr.changes = d.changes;
    dr.life_from_hours = d.continue_run.empty() ? d.scene.wear.start_hours : d.continue_hours;
    kind_lives_of(d, st, dr.kind_life_h, dr.kind_life_extrapolated);
    r.designs.push_back(std::move(dr));
  }
  RunEstimates e = run_estimates(ctx);
  r.replicates = ctx.plan.replicates;
  r.estimates = std::move(e.designs);
  r.history_estimates = std::move(e.histories);
  r.verdicts = std::move(e.verdicts);
  // The files on disk now (a file of an earlier stage may since have been replaced).
  r.files.push_back("manifest.json");
  for (const auto& f : ctx.written)
    if (f != "manifest.json" && io::file_exists(io::join_path(opt.out, f))) r.files.push_back(f);
  return r;
}

// summary.csv, spectrum.csv and manifest.json, from the stages so far. Caller holds the mutex.
void write_tables(RunState& ctx, const RunOptions& opt, bool final_write) {
  note(ctx, opt.out, io::summary_path(opt.out));
  note(ctx, opt.out, io::spectrum_path(opt.out));
  study::RunReport r = report_of(ctx, opt, final_write);
  study::write_summary(r);
  study::write_kinds(r);
  study::write_replicates(r);
  study::write_verdicts(r);
  for (const std::string& path : {study::kinds_path(opt.out), study::replicates_path(opt.out), study::verdicts_path(opt.out)}) {
    if (!io::file_exists(path)) continue;
    note(ctx, opt.out, path);
    const std::string rel = io::relative_to(opt.out, path);
    if (std::find(r.files.begin(), r.files.end(), rel) == r.files.end()) r.files.push_back(rel);
  }
  study::write_spectrum(r);
  study::write_manifest(r);
}

// One finished stage of design i: persist it (unless it was read back from disk), then
// update the shared tables. Runs on the design's thread.
void on_stage_done(RunState& ctx, const RunOptions& opt, std::size_t i, const StageRecord& rec) {
  const DesignInput& d = ctx.plan.designs[i];
  DesignState& st = *ctx.designs[i];
  const std::string& out = opt.out;
  study::write_profile_csv(out, d.name, rec);  // derived from the exact state: same on resume
  // Stages read back from OUT are on disk; those of the run --continue names are copied. A
  // stage heard of again is the resumed one worn through anew: its record carries the new
  // wear's errors (on a resume, the same bytes).
  // ParaView files of the stage's measuring window (a stage read back from disk has none),
  // before the stage's marker: a stage whose files could not be written is run again on
  // --resume, not skipped without them.
  std::vector<std::string> vtk_files;
  if (!rec.frames.empty()) {
    const MillGeometry mill = build_mill(d.scene.radius_m(), d.scene.mill.rows, rec.units, d.scene.mill.kind_count());
    const LinerFields fields{rec.edge_shear_W_per_m2, rec.edge_impact_W_per_m2, rec.edge_wear_rate_m_per_s};
    vtk_files = write_vtk_series(io::join_path(out, "vtk"), d.name + "_stage" + std::to_string(rec.stage), d.scene,
                                 mill, rec.frames, fields);
  }
  bool again = false;
  {
    std::lock_guard<std::mutex> lock(ctx.mutex);
    again = st.stages.count(rec.stage) > 0;
  }
  if (again || rec.stage > st.resumed_up_to || rec.stage <= st.copied_up_to)
    study::write_stage_state(out, d.name, rec);  // then the marker
  bool latest;
  {
    std::lock_guard<std::mutex> lock(ctx.mutex);
    // A worn-out record carries no charge: the snapshot keeps the last measured stage.
    latest = rec.stage > st.latest_written && rec.snapshot.size() > 0;
    if (latest) st.latest_written = rec.stage;
  }
  // The snapshot (unless outputs.snapshot is off) and liner files show the latest stage (only
  // this thread writes them).
  const bool snapshot = latest && d.scene.outputs.snapshot;
  if (snapshot) study::write_snapshot_csv(out, d.name, d.scene, rec);
  if (latest) study::write_liner_csv(out, d.name, d.scene, rec);
  StageRecord light = light_copy(rec);
  const std::vector<std::string> state_files = study::stage_state_files(out, d.name, rec.stage);
  std::lock_guard<std::mutex> lock(ctx.mutex);
  note(ctx, out, io::profile_path(out, d.name, rec.stage));
  for (const auto& f : state_files) note(ctx, out, f);
  for (const auto& f : vtk_files) note(ctx, out, f);
  if (snapshot) note(ctx, out, io::snapshot_path(out, d.name));
  if (latest) note(ctx, out, io::liner_path(out, d.name));
  st.stages[rec.stage] = std::move(light);
  write_tables(ctx, opt, false);
  const bool last = rec.stage >= d.scene.wear.stages || rec.worn_out;
  if (opt.stop_after_stage >= 0 && rec.stage >= opt.stop_after_stage &&
      rec.stage > st.resumed_up_to && !last) {
    // --stop-after-stage: this stage is on disk; leave the loop now, as an interrupt would.
    st.stop = true;
    throw StopRequested();
  }
}

void run_design(RunState& ctx, const RunOptions& opt, std::size_t i, const std::vector<StageRecord>& resume_from) {
  const DesignInput& d = ctx.plan.designs[i];
  DesignState& st = *ctx.designs[i];
  {
    std::lock_guard<std::mutex> lock(ctx.mutex);
    st.status = DesignStatus::Running;
    st.started = Clock::now();
  }
  WearCallbacks cb;
  cb.on_stage = [&ctx, &opt, i](const StageRecord& r) { on_stage_done(ctx, opt, i, r); };
  cb.on_progress = [&ctx, &st](const WearProgress& p) {
    std::lock_guard<std::mutex> lock(ctx.mutex);
    st.progress = p;
    st.progress_at = Clock::now();
  };
  cb.should_stop = [&opt, &st] { return stop_requested(opt) || st.stop.load(); };
  DesignStatus status = DesignStatus::Done;
  std::string error;
  WearHistory history;
  bool have = false;
  try {
    const bool complete = !resume_from.empty() && (resume_from.back().stage >= d.scene.wear.stages ||
                                                   resume_from.back().worn_out);
    if (complete) {
      // Every stage was read back: nothing left to simulate.
      history.stages = resume_from;
      if (d.scene.wear.rate_source == WearRateSource::Given)
        history.wear_rate_m3_per_J = d.scene.wear.wear_rate_m3_per_J;
      compute_life(history, d.scene.wear.replacement_height_m);
    } else {
      Scene scene = d.scene;
      scene.solver.threads = ctx.engine_threads;
      scene.solver.threads_fit_size = ctx.engine_threads_fit_size;
      history = run_wear_history(scene, cb, resume_from);
    }
    have = true;
    // Stopped by rule 1 or a lost disk: the finished stages stay, the design failed.
    if (!history.failure.empty()) {
      status = DesignStatus::Failed;
      error = history.failure;
    }
  } catch (const std::exception& e) {
    const bool stopping = stop_requested(opt) || st.stop.load();
    status = stopping ? DesignStatus::Interrupted : DesignStatus::Failed;
    error = e.what();
  }
  if (have && (stop_requested(opt) || st.stop.load()) &&
      static_cast<int>(history.stages.size()) <= d.scene.wear.stages) {
    // The loop returned early (stopped at a stage boundary) instead of throwing.
    status = DesignStatus::Interrupted;
    have = false;
  }
  std::lock_guard<std::mutex> lock(ctx.mutex);
  st.wall_s = std::chrono::duration<double>(Clock::now() - st.started).count();
  st.status = status;
  st.error = error;
  if (have) {
    st.have_history = true;
    st.life_h = history.life_h;
    st.life_extrapolated = history.life_extrapolated;
    st.wear_rate_m3_per_J = history.wear_rate_m3_per_J;
    st.events = history.events;
    // Stages the callback did not see (a loop that reports only new ones) come from here.
    for (const auto& r : history.stages)
      if (!st.stages.count(r.stage)) {
        st.stages[r.stage] = light_copy(r);
      }
  }
  try {
    write_tables(ctx, opt, false);
  } catch (const std::exception& e) {
    if (st.status == DesignStatus::Done) {
      st.status = DesignStatus::Failed;
      st.error = e.what();
    }
  }
}

io::KeyValues resume_key(const Plan& plan) {
  io::KeyValues kv;
  for (const auto& d : plan.designs) kv.emplace_back("design." + d.name, d.fingerprint);
  return kv;
}

// What differs between the plan's designs and those the run in OUT recorded in its manifest:
// the --set overrides, the fidelity, the run and stage a continuation goes on from (each named
// with the run's and this one's), else the scene or profile files' contents.
std::string changed_inputs(const Plan& plan, const std::string& out) {
  std::vector<std::string> sets_then, sets_now;
  std::string fidelity_then, fidelity_now, from_then = "none", from_now = "none";
  const auto from_text = [](const std::string& run, long long stage) {
    return run.empty() ? std::string("none") : run + " stage " + std::to_string(stage);
  };
  try {
    const nlohmann::json m = nlohmann::json::parse(io::read_file(io::manifest_path(out)));
    bool found = false;
    for (const auto& d : m.at("designs")) {
      for (const DesignInput& p : plan.designs)
        if (!found && p.name == d.at("name").get<std::string>()) {
          found = true;
          sets_then = d.at("set").get<std::vector<std::string>>();
          sets_now = p.scene.overrides;
          fidelity_then = d.at("fidelity").get<std::string>();
          fidelity_now = p.scene.fidelity;
          if (d.contains("continued_from"))
            from_then = from_text(d.at("continued_from").at("run").get<std::string>(),
                                  d.at("continued_from").at("stage").get<long long>());
          from_now = from_text(p.continue_run, p.continue_stage);
        }
    }
    if (!found) throw std::runtime_error("no design of this run in the manifest");
  } catch (const std::exception&) {
    return "other inputs: scene or profile files, --set overrides or fidelity";
  }
  auto joined = [](const std::vector<std::string>& v) {
    std::string t;
    for (const auto& x : v) t += (t.empty() ? "--set " : " --set ") + x;
    return t.empty() ? std::string("none") : t;
  };
  std::vector<std::string> reasons;
  if (sets_then != sets_now) reasons.push_back("--set overrides: " + joined(sets_then) + " then, " + joined(sets_now) + " now");
  if (fidelity_then != fidelity_now) reasons.push_back("fidelity: " + fidelity_then + " then, " + fidelity_now + " now");
  if (from_then != from_now) reasons.push_back("--continue: " + from_then + " then, " + from_now + " now");
  if (reasons.empty()) return "other scene or profile files";
  std::string text;
  for (const auto& r : reasons) text += (text.empty() ? "" : "; ") + r;
  return text;
}

// What OUT holds. None: no run.key and no manifest (a new folder, or the user's own files).
// Same: the same designs with the same fingerprints. Foreign: another command's results (a
// sweep's, a charge's), which --force does not delete. Other: anything else.
enum class Holds { None, Same, Foreign, Other };

Holds folder_holds(const Plan& plan, const std::string& out, std::string& what) {
  const std::string holder = io::folder_results_command(out);
  if (!holder.empty() && holder != "run") {
    what = "the results of `millwear " + holder + "`";
    return Holds::Foreign;
  }
  const std::string key = io::run_key_path(out);
  if (!io::file_exists(key)) {
    if (!io::file_exists(io::manifest_path(out))) return Holds::None;
    what = "a run whose inputs are not recorded (" + io::manifest_path(out) + " without " + key + ")";
    return Holds::Other;
  }
  io::KeyValues have;
  try {
    have = io::read_key_values(key);
  } catch (const InputError&) {
    what = "a run whose " + key + " does not read";
    return Holds::Other;
  }
  const io::KeyValues want = resume_key(plan);
  const std::set<std::pair<std::string, std::string>> a(have.begin(), have.end()), b(want.begin(), want.end());
  if (a == b) return Holds::Same;
  std::string names, changed;
  for (const auto& [k, v] : have) {
    if (k.compare(0, 7, "design.") != 0) continue;
    const std::string n = k.substr(7);
    names += (names.empty() ? "" : ", ") + n;
    for (const auto& d : plan.designs)
      if (d.name == n && d.fingerprint != v) changed += (changed.empty() ? "" : ", ") + n;
  }
  if (names.empty()) {
    what = "a run whose " + key + " names no design (damaged or cut short)";
    return Holds::Other;
  }
  what = "the results of design(s) " + names +
         (changed.empty() ? std::string(" (not the designs of this run)")
                          : " (" + changed_inputs(plan, out) + ", for " + changed + ")");
  return Holds::Other;
}

// A folder no run recorded may hold the user's own files, which a run keeps; but not under a
// name the run writes, which it would overwrite: the first such entry ("" if none).
std::string unrecorded_output(const Plan& plan, const std::string& out) {
  std::vector<std::string> names = {io::summary_path(out), io::join_path(out, "summary.md"), io::spectrum_path(out),
                                    io::join_path(out, "kinds.csv"), io::join_path(out, "replicates.csv"),
                                    io::profiles_dir(out), io::stages_dir(out), io::plots_out_dir(out),
                                    io::join_path(out, "inputs"), io::join_path(out, "vtk")};
  for (const auto& d : plan.designs) {
    names.push_back(io::snapshot_path(out, d.name));
    names.push_back(io::liner_path(out, d.name));
  }
  std::error_code ec;
  for (const std::string& n : names)
    if (fs::exists(fs::symlink_status(n, ec))) return n;
  return "";
}

// A folder of another run's results, taken over with --force: the first file the run would
// remove or overwrite that the earlier run did not write ("" if none). The earlier run's are
// those its manifest lists and the state of the designs its run.key names (what
// remove_run_outputs deletes); the rest, under a name this run writes (a table, or the
// snapshot, liner, stage state or profile of one of its designs), is a user's.
std::string unlisted_output(const Plan& plan, const std::string& out) {
  const std::vector<std::string> files = io::manifest_files(out);
  const std::set<std::string> listed(files.begin(), files.end());
  std::set<std::string> recorded;
  try {
    for (const auto& [k, v] : io::read_key_values(io::run_key_path(out)))
      if (k.compare(0, 7, "design.") == 0) recorded.insert(k.substr(7));
  } catch (const std::exception&) {
  }
  std::vector<std::string> names = {"summary.md", "kinds.csv", "replicates.csv"};
  // The names remove_stage_state takes.
  const auto stage_file = [](const std::string& dir, const std::string& n, const std::string& design) {
    return dir == "stages" ? study::is_stage_state_name(n, design) : study::is_stage_profile_name(n, design);
  };
  std::error_code ec;
  for (const DesignInput& d : plan.designs) {
    if (recorded.count(d.name)) continue;
    names.push_back("snapshot_" + d.name + ".csv");
    names.push_back("liner_" + d.name + ".csv");
    for (const std::string& dir : {std::string("stages"), std::string("profiles")})
      if (fs::is_directory(io::join_path(out, dir), ec))
        for (const auto& e : fs::directory_iterator(io::join_path(out, dir), ec))
          if (stage_file(dir, e.path().filename().string(), d.name))
            names.push_back(dir + "/" + e.path().filename().string());
  }
  for (const std::string& n : names)
    if (!listed.count(n) && fs::exists(fs::symlink_status(io::join_path(out, n), ec))) return io::join_path(out, n);
  return "";
}

// Every file a run of the plan writes into OUT whose name is known before it runs, relative
// to OUT: the tables, the manifest, the run key, each design's snapshot, liner and stage
// files, the figures and the inputs' copies.
std::vector<std::string> run_output_names(const Plan& plan) {
  std::vector<std::string> names = {"manifest.json", "summary.csv", "summary.md", "spectrum.csv", "kinds.csv",
                                    "replicates.csv", "stages/run.key", "plots/gnuplot.log"};
  std::vector<std::string> figures = {"fig6_profiles", "fig7_area", "fig8_power", "fig9_collision",
                                      "fig10_utilization", "spectrum", "kinds_area"};
  for (const std::string& f : plan.comparison_files) names.push_back("inputs/" + fs::path(f).filename().string());
  for (const DesignInput& d : plan.designs) {
    names.push_back("snapshot_" + d.name + ".csv");
    names.push_back("liner_" + d.name + ".csv");
    figures.push_back("snapshot_" + d.name);
    for (const std::string& f : d.files) names.push_back("inputs/" + fs::path(f).filename().string());
    for (int k = 0; k <= d.scene.wear.stages; ++k)
      for (std::string& n : study::stage_file_names(d.name, k)) names.push_back(std::move(n));
  }
  for (const std::string& f : figures)
    for (const char* ext : {".png", ".svg"}) names.push_back("plots/" + f + ext);
  return names;
}

// Every file the plan reads: a run started from the copies in OUT/inputs/ keeps them.
std::vector<std::string> input_files(const Plan& plan) {
  std::vector<std::string> files = plan.comparison_files;
  for (const DesignInput& d : plan.designs) files.insert(files.end(), d.files.begin(), d.files.end());
  return files;
}

// What OUT holds, once the run may write there: throws InputError(OUT, "-o", ...) for a
// folder of another command's results, of another run's (unless force), or holding a file
// no run recorded under a name the run writes.
Holds check_folder(const Plan& plan, const std::string& out, bool force, std::string* found = nullptr) {
  // A folder where the run writes a file (a folder named summary.csv) is refused now, before
  // anything is deleted or run, not when that file is written.
  io::check_output_names(out, run_output_names(plan), "run");
  std::string holds_what;
  const Holds holds = folder_holds(plan, out, holds_what);
  if (found) *found = holds_what;
  if (holds == Holds::Foreign)
    throw InputError(out, "-o",
                     "a folder that is new or holds the results of these same scenes and settings, but it "
                     "holds " + holds_what + ", which a run would partly overwrite: use another folder");
  if (holds == Holds::Other && !force)
    throw InputError(out, "-o",
                     "a folder that is new or holds the results of these same scenes and settings, but it "
                     "holds " + holds_what + ". Use another folder, or --force to delete that run's files (those "
                     "its manifest.json lists; no other file is touched)");
  if (holds == Holds::Other)
    if (const std::string taken = unlisted_output(plan, out); !taken.empty())
      throw InputError(out, "-o",
                       "a folder whose earlier run --force deletes, but " + taken +
                           " is there and that run did not write it (its manifest.json does not list it); this run "
                           "would overwrite it: move it, or use another folder");
  // An input in OUT under a name the run writes (its copy in inputs/ aside: the same text
  // again), or among the earlier run's files that it deletes first, would be gone before it
  // is read: the stage profile of an earlier run given as a lifter, say.
  std::vector<std::string> taken_names;
  for (const std::string& n : run_output_names(plan))
    if (n.compare(0, 7, "inputs/") != 0) taken_names.push_back(n);
  if (holds != Holds::None) {
    for (const std::string& n : io::manifest_files(out))
      if (n.compare(0, 7, "inputs/") != 0) taken_names.push_back(n);
    // The stage files of the designs its run.key records (what remove_stage_state deletes).
    std::set<std::string> recorded;
    try {
      for (const auto& [k, v] : io::read_key_values(io::run_key_path(out)))
        if (k.compare(0, 7, "design.") == 0) recorded.insert(k.substr(7));
    } catch (const std::exception&) {
    }
    std::error_code ec;
    for (const std::string dir : {"stages", "profiles"})
      if (fs::is_directory(io::join_path(out, dir), ec))
        for (const auto& e : fs::directory_iterator(io::join_path(out, dir), ec)) {
          const std::string n = e.path().filename().string();
          for (const std::string& design : recorded)
            if (dir == "stages" ? study::is_stage_state_name(n, design) : study::is_stage_profile_name(n, design))
              taken_names.push_back(dir + "/" + n);
        }
  }
  io::check_inputs_not_among(out, taken_names, input_files(plan), "run");
  if (holds == Holds::None && io::folder_results_command(out).empty())
    if (const std::string taken = unrecorded_output(plan, out); !taken.empty())
      throw InputError(out, "-o",
                       "a folder that is new or holds a run's results, but " + taken +
                           " is there and no run recorded it (no manifest.json or stages/run.key); a run "
                           "would overwrite it: move it, or use another folder");
  return holds;
}

// Copies of every scene, profile and comparison file into OUT/inputs/ (file names kept;
// a second, different file with a name already taken gets its design's name in front).
void copy_inputs(RunState& ctx, const std::string& out) {
  const std::string dir = io::join_path(out, "inputs");
  io::ensure_dir(dir);
  std::map<std::string, std::string> taken;  // name -> content
  auto copy = [&](const std::string& path, const std::string& prefix) {
    const std::string content = io::read_file(path);
    std::string name = fs::path(path).filename().string();
    auto it = taken.find(name);
    if (it != taken.end() && it->second != content) name = prefix + "_" + name;
    if (!taken.count(name)) {
      io::write_file_atomic(io::join_path(dir, name), content);
      note(ctx, out, io::join_path(dir, name));
      taken[name] = content;
    }
    return name;
  };
  for (const auto& c : ctx.plan.comparison_files) copy(c, "comparison");
  for (const auto& d : ctx.plan.designs)
    for (const auto& f : d.files) ctx.copied[d.name].push_back(copy(f, d.name));
}

}  // namespace

void remove_run_outputs(const std::string& out, const std::vector<std::string>& keep) {
  std::vector<std::string> files = io::manifest_files(out);
  const std::string key = io::run_key_path(out);
  if (io::file_exists(key)) {
    try {
      for (const auto& [k, v] : io::read_key_values(key)) {
        if (k.compare(0, 7, "design.") != 0 || !io::is_valid_design_name(k.substr(7))) continue;
        const std::string n = k.substr(7);
        study::remove_stage_state(out, n);
        files.push_back(io::relative_to(out, io::snapshot_path(out, n)));
        files.push_back(io::relative_to(out, io::liner_path(out, n)));
      }
    } catch (const InputError&) {
    }
  }
  for (const std::string& f : {io::summary_path(out), io::spectrum_path(out), key, io::manifest_path(out)})
    files.push_back(io::relative_to(out, f));
  io::remove_run_files(out, files, keep);
}

std::string check_run_folder(const Plan& plan, const std::string& out, bool force, bool resume) {
  io::check_output_folder(out);
  std::error_code ec;
  if (!fs::is_directory(out, ec)) return "";
  std::string what;
  const Holds holds = check_folder(plan, out, force, &what);
  if (holds == Holds::Same)
    return out + " holds a run of these same inputs: " +
           (resume ? "the run continues after its finished stages"
                   : "the run first deletes that run's files (those its manifest.json lists) and starts over "
                     "(--resume continues it)");
  if (holds == Holds::Other) {
    return "--force: " + out + " holds " + what +
           "; the run first deletes that run's files (those its manifest.json lists; no other file)";
  }
  return "";
}

namespace {

// The local time as ISO 8601, for the manifest.
std::string local_time_text() {
  std::time_t t = std::time(nullptr);
  std::tm tm{};
  localtime_r(&t, &tm);
  char buf[64];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S%z", &tm);
  return buf;
}

// The stages each design goes on from: --resume reads this same run's finished stages from
// OUT; --continue those of the run it continues, up to the stage it goes on from (a resumed
// continuation reads them from OUT).
std::vector<std::vector<StageRecord>> earlier_stages(RunState& ctx, const std::string& out, bool resuming) {
  const Plan& plan = ctx.plan;
  std::vector<std::vector<StageRecord>> earlier(plan.designs.size());
  for (std::size_t i = 0; i < plan.designs.size(); ++i) {
    const DesignInput& d = plan.designs[i];
    if (resuming) {
      const int k = std::min(io::last_finished_stage(out, d.name), d.scene.wear.stages);
      for (int s = 0; s <= k; ++s) earlier[i].push_back(study::read_stage_state(out, d.name, s));
      ctx.designs[i]->resumed_up_to = k;
      // A continued run stopped before it had copied every stage up to N: the rest from RUN.
      if (!d.continue_run.empty() && k < d.continue_stage) {
        for (int s = k + 1; s <= d.continue_stage; ++s)
          earlier[i].push_back(study::read_stage_state(d.continue_run, d.name, s));
        if (d.refill) earlier[i].back().start_charge = ChargeState{};
        ctx.designs[i]->resumed_up_to = ctx.designs[i]->copied_up_to = d.continue_stage;
      }
    } else if (!d.continue_run.empty()) {
      for (int s = 0; s <= d.continue_stage; ++s) earlier[i].push_back(study::read_stage_state(d.continue_run, d.name, s));
      // Stage N's record then says so too: a resume of this run fills the same charge anew.
      if (d.refill) earlier[i].back().start_charge = ChargeState{};
      ctx.designs[i]->resumed_up_to = ctx.designs[i]->copied_up_to = d.continue_stage;
    }
  }
  return earlier;
}

// The run folder made ready: stale temporaries gone; unless resuming, the files of an
// earlier run of these inputs removed; the run key and the inputs' copies written.
void prepare_folder(RunState& ctx, const std::string& out, bool resuming) {
  const Plan& plan = ctx.plan;
  io::create_run_folder(out);
  for (const std::string& dir : {out, io::stages_dir(out), io::profiles_dir(out), io::plots_out_dir(out),
                                 io::plots_data_dir(out), io::join_path(out, "inputs")})
    io::remove_stale_temps(dir);
  if (!resuming) {
    std::error_code ec;
    for (const auto& d : plan.designs) {
      study::remove_stage_state(out, d.name);
      fs::remove(io::snapshot_path(out, d.name), ec);
      fs::remove(io::liner_path(out, d.name), ec);
    }
    for (const std::string& f : {io::summary_path(out), io::spectrum_path(out), study::kinds_path(out),
                                 study::replicates_path(out), study::verdicts_path(out)})
      fs::remove(f, ec);
  }
  io::write_file_atomic(io::run_key_path(out), io::format_key_values(resume_key(plan), "millwear run inputs (for --resume)"));
  ctx.written.insert(io::relative_to(out, io::run_key_path(out)));
  copy_inputs(ctx, out);
}

// Every design to its end (or to a stop), ctx.jobs at once; the progress ticks meanwhile.
void run_all(RunState& ctx, const RunOptions& opt, const std::vector<std::vector<StageRecord>>& earlier) {
  const std::size_t n = ctx.plan.designs.size();
  std::atomic<std::size_t> next{0};
  std::atomic<std::size_t> finished{0};
  const auto work = [&](int) {
    for (std::size_t i; (i = next.fetch_add(1)) < n;) {
      if (stop_requested(opt)) {
        std::lock_guard<std::mutex> lock(ctx.mutex);
        ctx.designs[i]->status = DesignStatus::Interrupted;
        continue;
      }
      run_design(ctx, opt, i, earlier[i]);
    }
    finished.fetch_add(1);
  };
  // As many of ctx.jobs as the system starts; none started, the designs run here in turn.
  std::vector<std::thread> workers = start_threads(ctx.jobs, work);
  if (workers.empty()) work(0);
  while (finished.load() < workers.size()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    std::lock_guard<std::mutex> lock(ctx.mutex);
    tick(opt);
  }
  for (auto& w : workers) w.join();
  std::lock_guard<std::mutex> lock(ctx.mutex);
  tick(opt);
}

// The figures from whatever finished, then the manifest again listing them and their data.
void draw_figures(RunState& ctx, const RunOptions& opt, RunOutcome& outcome) {
  const std::string& out = opt.out;
  const std::vector<std::string> names = design_names(ctx.plan);
  std::vector<std::string> figures;
  try {
    figures = plots::render_all_figures(out, names, ctx.plan.reference);
  } catch (const std::exception& e) {
    outcome.figures_failed = plots::gnuplot_available();
    outcome.figure_error = e.what();
  }
  std::lock_guard<std::mutex> lock(ctx.mutex);
  outcome.figures_written = figures.size();
  for (const auto& f : figures) note(ctx, out, f);
  for (const auto& f : plots::figure_data_files(out, names)) note(ctx, out, f);
  study::write_manifest(report_of(ctx, opt, true));
}

}  // namespace

RunOutcome run_designs(RunState& ctx, const RunOptions& opt) {
  const Plan& plan = ctx.plan;
  ctx.started_text = local_time_text();
  for (std::size_t i = 0; i < plan.designs.size(); ++i) ctx.designs.push_back(std::make_unique<DesignState>());
  ctx.jobs = jobs_for(opt.jobs, plan.designs.size());
  // The cores the designs at once leave go to their steps.
  ctx.engine_threads = step_threads_beside(opt.threads, ctx.jobs);
  ctx.engine_threads_fit_size = opt.threads == 0;

  // One run per folder, for the whole run: a second one is refused here, before it reads
  // or deletes anything.
  const std::string& out = opt.out;
  std::optional<io::FolderLock> folder_lock;
  if (opt.lock_folder) folder_lock.emplace(out);

  // A folder holding another run's results is not mixed with this one's: refused, or with
  // --force cleared of that run's files (and only those) first.
  // The same run without --resume starts over: nothing of its earlier files (a figure an
  // interrupted run would not draw again) stays beside the new ones.
  const Holds holds = check_folder(plan, out, opt.force);
  if (holds == Holds::Other || (holds == Holds::Same && !opt.resume)) remove_run_outputs(out, input_files(plan));
  io::ensure_dir(out);
  io::mark_folder(out, "run");
  ctx.written.insert(io::relative_to(out, io::folder_mark_path(out)));

  // --resume continues the stages of this same run (the check above). Files an earlier run
  // of these same inputs wrote stay listed while they are on disk.
  const bool resuming = opt.resume && holds == Holds::Same;
  if (holds == Holds::Same)
    for (const auto& f : io::manifest_files(out)) ctx.written.insert(f);
  const std::vector<std::vector<StageRecord>> earlier = earlier_stages(ctx, out, resuming);
  prepare_folder(ctx, out, resuming);

  // Stages read back: the same bookkeeping as freshly finished ones (files rewritten from
  // the exact state, so they match an uninterrupted run).
  for (std::size_t i = 0; i < plan.designs.size(); ++i)
    for (const auto& r : earlier[i]) on_stage_done(ctx, opt, i, r);
  {
    std::lock_guard<std::mutex> lock(ctx.mutex);
    ctx.resumed = resuming;
    write_tables(ctx, opt, false);
    tick(opt);
  }

  run_all(ctx, opt, earlier);

  RunOutcome outcome;
  for (const auto& st : ctx.designs) {
    outcome.failed = outcome.failed || st->status == DesignStatus::Failed;
    outcome.interrupted = outcome.interrupted || st->status == DesignStatus::Interrupted;
  }
  outcome.signal = opt.stop_signal ? opt.stop_signal->load() : 0;
  {
    std::lock_guard<std::mutex> lock(ctx.mutex);
    write_tables(ctx, opt, !outcome.interrupted);
  }
  if (!outcome.interrupted && opt.figures) draw_figures(ctx, opt, outcome);
  if (!outcome.interrupted && opt.stop_signal && opt.stop_signal->load() != 0 && !outcome.figure_error.empty()) {
    // A figure that failed while a stop came (Ctrl-C reaches gnuplot too): an interruption,
    // not a figure that failed. Every stage is on disk; --resume draws the figures again. A
    // stop that came once every figure was drawn found the run finished, and it stays so.
    outcome.interrupted = true;
    outcome.signal = opt.stop_signal->load();
    outcome.figures_failed = false;
    outcome.figure_error.clear();
    std::lock_guard<std::mutex> lock(ctx.mutex);
    study::write_manifest(report_of(ctx, opt, false));
  }
  outcome.wall_s = std::chrono::duration<double>(Clock::now() - ctx.t0).count();
  return outcome;
}

}  // namespace millwear::study
