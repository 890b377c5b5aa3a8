// `millwear run SCENE... -o OUT`: the wear history of every design, compared.
//
// A SCENE argument is either a scene file (one design, named by the scene's `name`) or a
// comparison file:
//
//   [comparison]
//   name = "sag-2x30-vs-1x30"                        # optional, for the record
//   description = "..."                              # optional
//   designs = ["sag-2x30.toml", "sag-1x30.toml"]     # scene files, relative to this file
//   reference = "sag-1x30"                           # design whose new stage normalises
//                                                    # (default: the first design)
//
// Every scene is read and validated before anything is written (exit 2 on bad input).
// Designs run in parallel, one thread per design up to --jobs. The wear library never
// prints; this file owns the terminal: live progress on a terminal, a summary at the end.
//
// Exit codes: 0 every design finished; 1 a design failed (the others still finish) or a
// figure failed; 2 bad input; 130 (143 for SIGTERM) interrupted: finished stages are on
// disk and `--resume` continues.
#include <CLI/CLI.hpp>
#include <toml++/toml.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "app/commands.hpp"
#include "app/duration_text.hpp"
#include "app/run_command.hpp"
#include "app/run_files.hpp"
#include "common/errors.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/run_folder.hpp"
#include "plots/plots.hpp"
#include "scene/fidelity.hpp"
#include "scene/limits.hpp"
#include "scene/scene.hpp"
#include "wear/wear.hpp"

namespace millwear::app {

namespace fs = std::filesystem;

namespace {

// ---------------------------------------------------------------------------------------
// Command line

// RunArgs: app/run_command.hpp (shared with `millwear screen-task`).

// ---------------------------------------------------------------------------------------
// Input: scenes and comparison files -> designs

struct DesignInput {
  std::string name;
  Scene scene;
  std::vector<std::string> files;  // scene file, profile file(s) it reads
  std::string fingerprint;         // of the file contents and fidelity (resume check)
};

struct Plan {
  std::vector<DesignInput> designs;
  std::string reference;
  std::vector<std::string> comparison_files;
  std::string fidelity;  // the override, or the shared fidelity of the scenes, or "mixed"
};

std::string hex(std::size_t v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%016zx", v);
  return buf;
}

// A profile file and every profile it reads (match_area_of), in reading order.
void profile_files(const std::string& path, std::vector<std::string>& files, int depth = 0) {
  if (path.empty() || depth > 8) return;
  if (std::find(files.begin(), files.end(), path) != files.end()) return;
  files.push_back(path);
  try {
    toml::table t = toml::parse_file(path);
    if (auto m = t["match_area_of"].value<std::string>())
      profile_files((fs::path(path).parent_path() / *m).lexically_normal().string(), files, depth + 1);
  } catch (const toml::parse_error&) {
    // load_scene already read it; nothing more to copy
  }
}

void add_design(Plan& plan, const std::string& scene_file, const std::string& fidelity_override) {
  Scene scene = load_scene(scene_file);  // throws InputError naming the file and key
  if (!fidelity_override.empty()) apply_fidelity(scene, fidelity_override);
  // The measured limits too, so a scene outside them stops here (exit 2), before any work.
  check_numerical_limits(scene, scene_file);
  check_smoothing_radius(scene, scene_file);
  if (!io::is_valid_design_name(scene.name))
    throw InputError(scene_file, "name",
                     "a design name of letters, digits, '.', '-' and '_' (it names the output "
                     "files), found '" + scene.name + "'");
  for (const auto& d : plan.designs)
    if (d.name == scene.name)
      throw InputError(scene_file, "name",
                       "a design name different from that of " + d.scene.source_file + " ('" +
                           scene.name + "'): each design names its output files");
  DesignInput d;
  d.name = scene.name;
  d.files.push_back(scene_file);
  profile_files(scene.mill.lifter.source_file, d.files);
  std::string all = scene.fidelity;
  for (const auto& f : d.files) all += "\n--\n" + io::read_file(f);
  d.fingerprint = hex(std::hash<std::string>{}(all));
  d.scene = std::move(scene);
  plan.designs.push_back(std::move(d));
}

// Returns the comparison table if the file is a comparison file, else nullopt (a scene,
// or a file load_scene will reject with a better message).
std::optional<toml::table> comparison_table(const std::string& path) {
  try {
    toml::table t = toml::parse_file(path);
    if (t.contains("comparison")) return t;
  } catch (const toml::parse_error&) {
  }
  return std::nullopt;
}

void add_comparison(Plan& plan, const std::string& file, const toml::table& root,
                    const std::string& fidelity_override, std::string& reference) {
  for (const auto& [k, v] : root)
    if (k.str() != "comparison")
      throw InputError(file, std::string(k.str()),
                       "only a [comparison] table in a comparison file (designs, reference, "
                       "name, description)");
  const toml::table* c = root["comparison"].as_table();
  if (!c) throw InputError(file, "comparison", "a table: [comparison] with designs = [...]");
  const std::set<std::string> allowed{"designs", "reference", "name", "description"};
  for (const auto& [k, v] : *c)
    if (!allowed.count(std::string(k.str())))
      throw InputError(file, "comparison." + std::string(k.str()),
                       "one of designs, reference, name, description");
  for (const char* key : {"name", "description"})
    if (c->contains(key) && !(*c)[key].is_string())
      throw InputError(file, std::string("comparison.") + key, "a string");
  const toml::array* designs = (*c)["designs"].as_array();
  if (!designs)
    throw InputError(file, "comparison.designs",
                     "an array of scene files, relative to this file, e.g. designs = "
                     "[\"sag-2x30.toml\", \"sag-1x30.toml\"]");
  if (designs->empty())
    throw InputError(file, "comparison.designs", "at least one scene file");
  const fs::path dir = fs::path(file).parent_path();
  const std::size_t first = plan.designs.size();
  for (std::size_t i = 0; i < designs->size(); ++i) {
    const std::string key = "comparison.designs[" + std::to_string(i) + "]";
    auto rel = (*designs)[i].value<std::string>();
    if (!rel || rel->empty()) throw InputError(file, key, "a scene file name (a string)");
    const std::string path = (dir / *rel).lexically_normal().string();
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
      throw InputError(file, key, "an existing scene file, relative to the comparison file; tried '" + path + "'");
    if (comparison_table(path))
      throw InputError(file, key, "a scene file, not another comparison file ('" + path + "')");
    add_design(plan, path, fidelity_override);
  }
  if (c->contains("reference")) {
    auto ref = (*c)["reference"].value<std::string>();
    if (!ref) throw InputError(file, "comparison.reference", "a design name (a string)");
    bool found = false;
    std::string names;
    for (std::size_t i = first; i < plan.designs.size(); ++i) {
      found = found || plan.designs[i].name == *ref;
      names += (names.empty() ? "" : ", ") + plan.designs[i].name;
    }
    if (!found)
      throw InputError(file, "comparison.reference",
                       "the name of one of its designs (" + names + "), found '" + *ref + "'");
    if (reference.empty()) reference = *ref;
  }
  plan.comparison_files.push_back(file);
}

Plan make_plan(const RunArgs& args) {
  if (!args.fidelity.empty()) fidelity_preset(args.fidelity);  // InputError for a bad name
  Plan plan;
  std::string reference;
  for (const auto& path : args.scenes) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
      throw InputError(path, "", "a scene or comparison file (not found or not a regular file)");
    if (auto t = comparison_table(path))
      add_comparison(plan, path, *t, args.fidelity, reference);
    else
      add_design(plan, path, args.fidelity);
  }
  if (plan.designs.empty()) throw InputError("", "SCENE", "at least one scene file");
  if (!args.reference.empty()) {
    bool found = false;
    for (const auto& d : plan.designs) found = found || d.name == args.reference;
    if (!found) throw InputError("", "--reference", "the name of one of the designs, found '" + args.reference + "'");
    reference = args.reference;
  }
  plan.reference = reference.empty() ? plan.designs.front().name : reference;
  if (!args.fidelity.empty()) {
    plan.fidelity = args.fidelity;
  } else {
    plan.fidelity = plan.designs.front().scene.fidelity;
    for (const auto& d : plan.designs)
      if (d.scene.fidelity != plan.fidelity) plan.fidelity = "mixed";
  }
  std::error_code ec;
  if (fs::exists(args.out, ec) && !fs::is_directory(args.out, ec))
    throw InputError(args.out, "-o", "an output folder, but a file of that name exists");
  return plan;
}

}  // namespace

std::vector<Scene> load_designs(const std::string& path) {
  RunArgs args;
  args.scenes = {path};
  std::vector<Scene> scenes;
  for (auto& d : make_plan(args).designs) scenes.push_back(std::move(d.scene));
  return scenes;
}

namespace {

// ---------------------------------------------------------------------------------------
// Run state shared between the design threads and the main thread (one mutex).

std::atomic<int> g_signal{0};

extern "C" void on_signal(int sig) {
  if (g_signal.load() != 0) {  // second Ctrl-C: stop now
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  g_signal.store(sig);
}

class SignalScope {
 public:
  SignalScope() {
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
  }
  ~SignalScope() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
  }

 private:
  struct sigaction old_int_ {}, old_term_ {};
};

// Thrown from on_stage by --stop-after-stage; the wear loop passes it through.
struct StopRequested : std::runtime_error {
  StopRequested() : std::runtime_error("stopped after the requested stage (--stop-after-stage)") {}
};

enum class Status { Waiting, Running, Done, Failed, Interrupted };

const char* status_name(Status s) {
  switch (s) {
    case Status::Waiting: return "waiting";
    case Status::Running: return "running";
    case Status::Done: return "finished";
    case Status::Failed: return "failed";
    case Status::Interrupted: return "interrupted";
  }
  return "?";
}

using Clock = std::chrono::steady_clock;

struct DesignState {
  Status status = Status::Waiting;
  std::string error;
  std::map<int, StageRecord> stages;  // light copies: no charge state, no edge rates
  int resumed_up_to = -1;             // stages 0..K were read back from disk
  int latest_written = -1;            // stage of the snapshot/liner files
  bool have_history = false;
  double life_h = std::nan("");
  bool life_extrapolated = false;
  double wear_rate_m3_per_J = std::nan("");
  std::vector<std::string> events;
  WearProgress progress;
  Clock::time_point progress_at;      // when progress last came
  Clock::time_point started;
  double wall_s = 0.0;
  std::atomic<bool> stop{false};
};

struct RunContext {
  const RunArgs& args;
  const Plan& plan;
  std::vector<std::unique_ptr<DesignState>> states;
  std::mutex mutex;
  std::string started_text;
  Clock::time_point t0;
  int jobs = 1;
  std::map<std::string, std::vector<std::string>> copied;  // design -> inputs/ names
};

double stage_total_hours(const Scene& s) { return s.wear.stage_hours * s.wear.stages; }

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

// summary.csv: one row per design and stage. Caller holds the mutex.
void write_summary(RunContext& ctx) {
  const auto& designs = ctx.plan.designs;
  io::CsvTable t({"design", "stage", "hours", "area_mm2", "area_norm", "area_loss_pct", "height_mm",
                  "power_kw", "power_norm", "collision_kw", "collision_norm", "utilization",
                  "utilization_norm", "life_h", "life_extrapolated", "packed_shear_pct"});
  // The reference design's new stage normalises every *_norm column.
  double ref_area = std::nan(""), ref_power = std::nan(""), ref_coll = std::nan(""), ref_util = std::nan("");
  for (std::size_t i = 0; i < designs.size(); ++i) {
    if (designs[i].name != ctx.plan.reference) continue;
    auto it = ctx.states[i]->stages.find(0);
    if (it == ctx.states[i]->stages.end()) break;
    const double len = designs[i].scene.mill.length_m;
    ref_area = it->second.lifter.area_m2 * 1e6;
    ref_power = it->second.charge.power_kW_per_m * len;
    ref_coll = it->second.charge.collision_kW_per_m * len;
    ref_util = ref_coll / ref_power;
  }
  for (std::size_t i = 0; i < designs.size(); ++i) {
    const DesignState& st = *ctx.states[i];
    if (st.stages.empty()) continue;
    const double len = designs[i].scene.mill.length_m;
    const auto own0 = st.stages.find(0);
    const double own_area = own0 != st.stages.end() ? own0->second.lifter.area_m2 * 1e6 : std::nan("");
    double life_h;
    bool extrapolated;
    life_of(designs[i], st, life_h, extrapolated);
    for (const auto& [k, r] : st.stages) {
      const double area = r.lifter.area_m2 * 1e6;
      const double power = r.charge.power_kW_per_m * len;  // kW per mill
      const double coll = r.charge.collision_kW_per_m * len;
      const double util = power != 0.0 ? coll / power : std::nan("");
      t.add_row({designs[i].name, k, r.hours, area, area / ref_area, 100.0 * (1.0 - area / own_area),
                 r.lifter.height_m * 1e3, power, power / ref_power, coll, coll / ref_coll, util,
                 util / ref_util, life_h, extrapolated, 100.0 * r.charge.summary.packed_shear_share});
    }
  }
  t.write(io::summary_path(ctx.args.out));
}

// spectrum.csv: the new stage's collision spectrum of each design. Caller holds the mutex.
void write_spectrum(RunContext& ctx) {
  io::CsvTable t({"design", "stage", "hours", "energy_J_lower", "energy_J_upper", "count_per_s", "energy_W"});
  for (std::size_t i = 0; i < ctx.plan.designs.size(); ++i) {
    // A scene that did not ask for the spectrum has none (zeros, not a measurement).
    if (!ctx.plan.designs[i].scene.outputs.collision_spectrum) continue;
    auto it = ctx.states[i]->stages.find(0);
    if (it == ctx.states[i]->stages.end()) continue;
    const StageRecord& r = it->second;
    const std::size_t n = std::min(r.spectrum_count_per_s.size(), r.spectrum_energy_W.size());
    for (std::size_t k = 0; k < n; ++k)
      t.add_row({ctx.plan.designs[i].name, 0, r.hours, spectrum_bin_lower_J(static_cast<int>(k)),
                 spectrum_bin_lower_J(static_cast<int>(k) + 1), r.spectrum_count_per_s[k],
                 r.spectrum_energy_W[k]});
  }
  t.write(io::spectrum_path(ctx.args.out));
}

const char* direction_name(Direction d) {
  switch (d) {
    case Direction::Forward: return "forward";
    case Direction::Reverse: return "reverse";
    case Direction::Bidirectional: return "bidirectional";
  }
  return "?";
}

io::JsonValue scene_settings(const Scene& s) {
  io::JsonValue j;
  j.object("mill")
      .set("diameter_m", s.mill.diameter_m)
      .set("length_m", s.mill.length_m)
      .set("slice_thickness_m", s.slice_thickness())
      .set("speed_fraction_critical", s.mill.speed_fraction_critical)
      .set("speed_rpm", s.angular_speed_rad_s() * 60.0 / (2.0 * 3.14159265358979323846))
      .set("direction", direction_name(s.mill.direction))
      .set("reverse_every_hours", s.mill.reverse_every_hours)
      .set("rows", s.mill.rows)
      .set("lifter_profile", s.mill.lifter.name)
      .set("shell_edge_m", s.mill.mesh.shell_edge_m)
      .set("lifter_edge_m", s.mill.mesh.lifter_edge_m);
  j.object("charge")
      .set("filling", s.charge.filling)
      .set("ball_filling", s.charge.ball_filling)
      .set("bulk_packing", s.charge.bulk_packing)
      .set("species", static_cast<int>(s.charge.species.size()));
  j.object("solver")
      .set("backend", s.solver.backend == Backend::Box2D ? "box2d" : "soft")
      .set("time_step_s", s.solver.time_step_s)
      .set("velocity_iterations", s.solver.velocity_iterations)
      .set("position_iterations", s.solver.position_iterations)
      .set("substeps", s.solver.substeps)
      .set("settle_time_s", s.solver.settle_time_s)
      .set("spinup_revolutions", s.solver.spinup_revolutions)
      .set("seed", static_cast<unsigned long long>(s.solver.seed))
      .set("size_cutoff_m", s.solver.size_cutoff_m);
  const WearDef& w = s.wear;
  j.object("wear")
      .set("mode", w.mode == WearMode::Staged ? "staged" : "continuous")
      .set("rate_source", w.rate_source == WearRateSource::Given          ? "given"
                          : w.rate_source == WearRateSource::AreaLossRate ? "area_loss_rate"
                                                                          : "height_loss_rate")
      .set("wear_rate_m3_per_J", w.wear_rate_m3_per_J)
      .set("calibration_value", w.calibration_value)
      .set("factor", w.factor)
      .set("stage_hours", w.stage_hours)
      .set("stages", w.stages)
      .set("window_revolutions", w.window_revolutions)
      .set("max_depth_step_m", w.max_depth_step_m)
      .set("update_interval_s", w.update_interval_s)
      .set("smoothing_radius_m", w.smoothing_radius_m)
      .set("average_rows", w.average_rows)
      .set("shell_wear", w.shell_wear)
      .set("replacement_height_m", w.replacement_height_m)
      .set("target_rel_uncertainty", w.target_rel_uncertainty);
  return j;
}

// manifest.json. Caller holds the mutex.
void write_manifest(RunContext& ctx, bool final_write) {
  io::JsonValue m;
  m.set("program", "millwear").set("version", MILLWEAR_VERSION);
  m.set("started", ctx.started_text);
  m.set("finished", final_write);
  m.set("wall_s", std::chrono::duration<double>(Clock::now() - ctx.t0).count());
  m.set("fidelity", ctx.plan.fidelity);
  m.set("reference", ctx.plan.reference);
  m.set("resumed", ctx.args.resume);
  m.set("jobs", ctx.jobs);
  io::JsonValue comps = io::JsonValue::array();
  for (const auto& c : ctx.plan.comparison_files) comps.push(c);
  m.set("comparison_files", comps);
  io::JsonValue designs = io::JsonValue::array();
  for (std::size_t i = 0; i < ctx.plan.designs.size(); ++i) {
    const DesignInput& d = ctx.plan.designs[i];
    const DesignState& st = *ctx.states[i];
    io::JsonValue j;
    j.set("name", d.name).set("scene_file", d.files.front());
    io::JsonValue files = io::JsonValue::array(), copies = io::JsonValue::array();
    for (const auto& f : d.files) files.push(f);
    for (const auto& f : ctx.copied[d.name]) copies.push("inputs/" + f);
    j.set("input_files", files).set("input_copies", copies);
    j.set("seed", static_cast<unsigned long long>(d.scene.solver.seed));
    j.set("fidelity", d.scene.fidelity);
    j.set("status", status_name(st.status));
    if (!st.error.empty()) j.set("error", st.error);
    j.set("resumed_stages", st.resumed_up_to + 1);
    double life_h;
    bool extrapolated;
    life_of(d, st, life_h, extrapolated);
    j.set("life_h", life_h).set("life_extrapolated", extrapolated);
    j.set("wear_rate_m3_per_J", st.wear_rate_m3_per_J);
    j.set("settings", scene_settings(d.scene));
    io::JsonValue stages = io::JsonValue::array();
    for (const auto& [k, r] : st.stages) {
      io::JsonValue s;
      s.set("stage", k).set("hours", r.hours).set("wall_s", r.wall_s).set("simulated_s", r.simulated_s)
          .set("disk_steps", static_cast<long long>(r.disk_steps))
          .set("resumed", k <= st.resumed_up_to);
      stages.push(s);
    }
    j.set("stages", stages);
    io::JsonValue events = io::JsonValue::array();
    for (const auto& e : st.events) events.push(e);
    j.set("events", events);
    designs.push(j);
  }
  m.set("designs", designs);
  io::write_file_atomic(io::manifest_path(ctx.args.out), m.dump(2) + "\n");
}

// One finished stage of design i: persist it (unless it was read back from disk), then
// update the shared tables. Runs on the design's thread.
void on_stage_done(RunContext& ctx, std::size_t i, const StageRecord& rec) {
  const DesignInput& d = ctx.plan.designs[i];
  DesignState& st = *ctx.states[i];
  const std::string& out = ctx.args.out;
  write_profile_csv(out, d.name, rec);  // derived from the exact state: same on resume
  if (rec.stage > st.resumed_up_to) write_stage_state(out, d.name, rec);  // then the marker
  bool latest;
  {
    std::lock_guard<std::mutex> lock(ctx.mutex);
    // A worn-out record carries no charge: the snapshot keeps the last measured stage.
    latest = rec.stage > st.latest_written && rec.snapshot.size() > 0;
    if (latest) st.latest_written = rec.stage;
  }
  // The snapshot and liner files show the latest stage (only this thread writes them).
  if (latest) {
    write_snapshot_csv(out, d.name, d.scene, rec);
    write_liner_csv(out, d.name, d.scene, rec);
  }
  StageRecord light = rec;
  light.snapshot = ChargeState{};
  light.start_charge = ChargeState{};
  light.edge_wear_rate_m_per_h.clear();
  std::lock_guard<std::mutex> lock(ctx.mutex);
  st.stages[rec.stage] = std::move(light);
  write_summary(ctx);
  if (rec.stage == 0) write_spectrum(ctx);
  write_manifest(ctx, false);
  const bool last = rec.stage >= d.scene.wear.stages || rec.worn_out;
  if (ctx.args.stop_after_stage >= 0 && rec.stage >= ctx.args.stop_after_stage &&
      rec.stage > st.resumed_up_to && !last) {
    // --stop-after-stage: this stage is on disk; leave the loop now, as an interrupt would.
    st.stop = true;
    throw StopRequested();
  }
}

void run_design(RunContext& ctx, std::size_t i, const std::vector<StageRecord>& resume_from) {
  const DesignInput& d = ctx.plan.designs[i];
  DesignState& st = *ctx.states[i];
  {
    std::lock_guard<std::mutex> lock(ctx.mutex);
    st.status = Status::Running;
    st.started = Clock::now();
  }
  WearCallbacks cb;
  cb.on_stage = [&ctx, i](const StageRecord& r) { on_stage_done(ctx, i, r); };
  cb.on_progress = [&ctx, &st](const WearProgress& p) {
    std::lock_guard<std::mutex> lock(ctx.mutex);
    st.progress = p;
    st.progress_at = Clock::now();
  };
  cb.should_stop = [&st] { return g_signal.load() != 0 || st.stop.load(); };
  Status status = Status::Done;
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
      history = run_wear_history(d.scene, cb, resume_from);
    }
    have = true;
  } catch (const std::exception& e) {
    const bool stopping = g_signal.load() != 0 || st.stop.load();
    status = stopping ? Status::Interrupted : Status::Failed;
    error = e.what();
  }
  if (have && (g_signal.load() != 0 || st.stop.load()) &&
      static_cast<int>(history.stages.size()) <= d.scene.wear.stages) {
    // The loop returned early (stopped at a stage boundary) instead of throwing.
    status = Status::Interrupted;
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
        StageRecord light = r;
        light.snapshot = ChargeState{};
        light.start_charge = ChargeState{};
        light.edge_wear_rate_m_per_h.clear();
        st.stages[r.stage] = std::move(light);
      }
  }
  try {
    write_summary(ctx);
    write_manifest(ctx, false);
  } catch (const std::exception& e) {
    if (st.status == Status::Done) {
      st.status = Status::Failed;
      st.error = e.what();
    }
  }
}

// ---------------------------------------------------------------------------------------
// Terminal progress

// One line per design. Caller holds the mutex.
std::string progress_line(const RunContext& ctx, std::size_t i, std::size_t name_width) {
  const DesignInput& d = ctx.plan.designs[i];
  const DesignState& st = *ctx.states[i];
  char buf[320];
  const int w = static_cast<int>(name_width);
  switch (st.status) {
    case Status::Waiting:
      std::snprintf(buf, sizeof buf, "%-*s  waiting for a free job", w, d.name.c_str());
      break;
    case Status::Running: {
      const double total = stage_total_hours(d.scene);
      const double start_h = st.resumed_up_to >= 0 && st.stages.count(st.resumed_up_to)
                                 ? st.stages.at(st.resumed_up_to).hours : 0.0;
      const double done_h = st.progress.hours - start_h, left_h = total - st.progress.hours;
      const double elapsed = std::chrono::duration<double>(Clock::now() - st.started).count();
      // Time left: the rate up to the last report, less the time since that report.
      const double at_report = std::chrono::duration<double>(st.progress_at - st.started).count();
      const double since = std::chrono::duration<double>(Clock::now() - st.progress_at).count();
      const double eta = done_h > 0 ? std::max(0.0, at_report * left_h / done_h - since) : std::nan("");
      // The wear loop reports after each stage; before the first report only time runs.
      if (st.progress.simulated_s <= 0.0)
        std::snprintf(buf, sizeof buf, "%-*s  stage %d/%d  %7.0f h  measuring the %s liner ...  elapsed %s",
                      w, d.name.c_str(), std::max(0, st.resumed_up_to), d.scene.wear.stages, start_h,
                      st.resumed_up_to > 0 ? "worn" : "new", duration_text(elapsed).c_str());
      else
        std::snprintf(buf, sizeof buf,
                      "%-*s  stage %d/%d  %7.0f h  sim %8.1f s  %6.2f M disk-steps/s  elapsed %s  left %s",
                      w, d.name.c_str(), st.progress.stage, d.scene.wear.stages, st.progress.hours,
                      st.progress.simulated_s, st.progress.disk_steps_per_s / 1e6,
                      duration_text(elapsed).c_str(), duration_text(eta).c_str());
      break;
    }
    case Status::Done:
      std::snprintf(buf, sizeof buf, "%-*s  finished in %s", w, d.name.c_str(), duration_text(st.wall_s).c_str());
      break;
    case Status::Failed:
      std::snprintf(buf, sizeof buf, "%-*s  FAILED: %.200s", w, d.name.c_str(), st.error.c_str());
      break;
    case Status::Interrupted:
      std::snprintf(buf, sizeof buf, "%-*s  interrupted", w, d.name.c_str());
      break;
  }
  return buf;
}

class ProgressView {
 public:
  ProgressView(RunContext& ctx, bool live) : ctx_(ctx), live_(live) {
    for (const auto& d : ctx.plan.designs) width_ = std::max(width_, d.name.size());
  }
  // Caller holds the mutex.
  void draw() {
    if (!live_) return;
    std::string s;
    if (drawn_) s += "\x1b[" + std::to_string(ctx_.plan.designs.size()) + "A";
    for (std::size_t i = 0; i < ctx_.plan.designs.size(); ++i)
      s += "\r\x1b[K" + progress_line(ctx_, i, width_) + "\n";
    std::fputs(s.c_str(), stderr);
    std::fflush(stderr);
    drawn_ = true;
  }

 private:
  RunContext& ctx_;
  bool live_;
  bool drawn_ = false;
  std::size_t width_ = 6;
};

// ---------------------------------------------------------------------------------------
// Output folder preparation

std::string resume_key_path(const std::string& out) { return io::join_path(io::stages_dir(out), "run.key"); }

io::KeyValues resume_key(const Plan& plan) {
  io::KeyValues kv;
  for (const auto& d : plan.designs) kv.emplace_back("design." + d.name, d.fingerprint);
  return kv;
}

// Copies of every scene, profile and comparison file into OUT/inputs/ (file names kept;
// a second, different file with a name already taken gets its design's name in front).
void copy_inputs(RunContext& ctx) {
  const std::string dir = io::join_path(ctx.args.out, "inputs");
  io::ensure_dir(dir);
  std::map<std::string, std::string> taken;  // name -> content
  auto copy = [&](const std::string& path, const std::string& prefix) {
    const std::string content = io::read_file(path);
    std::string name = fs::path(path).filename().string();
    auto it = taken.find(name);
    if (it != taken.end() && it->second != content) name = prefix + "_" + name;
    if (!taken.count(name)) {
      io::write_file_atomic(io::join_path(dir, name), content);
      taken[name] = content;
    }
    return name;
  };
  for (const auto& c : ctx.plan.comparison_files) copy(c, "comparison");
  for (const auto& d : ctx.plan.designs)
    for (const auto& f : d.files) ctx.copied[d.name].push_back(copy(f, d.name));
}

// ---------------------------------------------------------------------------------------

void print_final_summary(RunContext& ctx, double wall) {
  std::printf("%-*s %6s %8s %10s %8s %10s %10s %8s %10s\n", 16, "design", "stage", "hours",
              "area_mm2", "loss_%", "height_mm", "power_kW", "util", "life_h");
  for (std::size_t i = 0; i < ctx.plan.designs.size(); ++i) {
    const DesignInput& d = ctx.plan.designs[i];
    const DesignState& st = *ctx.states[i];
    double life_h;
    bool extrapolated;
    life_of(d, st, life_h, extrapolated);
    const auto own0 = st.stages.find(0);
    for (const auto& [k, r] : st.stages) {
      const double area = r.lifter.area_m2 * 1e6;
      const double loss = own0 != st.stages.end() ? 100.0 * (1.0 - r.lifter.area_m2 / own0->second.lifter.area_m2) : std::nan("");
      const double p = r.charge.power_kW_per_m * d.scene.mill.length_m;
      const double u = r.charge.collision_kW_per_m / r.charge.power_kW_per_m;
      std::printf("%-*s %6d %8.0f %10.1f %8.1f %10.1f %10.4g %8.3f %9.0f%s\n", 16, d.name.c_str(), k,
                  r.hours, area, loss, r.lifter.height_m * 1e3, p, u, life_h, extrapolated ? "*" : " ");
    }
    std::printf("%-*s %s%s%s\n", 16, st.stages.empty() ? d.name.c_str() : "", status_name(st.status),
                st.error.empty() ? "" : ": ", st.error.c_str());
    for (const auto& e : st.events) std::printf("%-*s event: %s\n", 16, "", e.c_str());
  }
  std::printf("(* life extrapolated from the stage trend; normalised to %s new; wall time %s)\n",
              ctx.plan.reference.c_str(), duration_text(wall).c_str());
}

}  // namespace

int run_command(const RunArgs& args) {
  const Plan plan = make_plan(args);  // every scene validated; nothing written yet
  if (args.check) {
    for (const auto& d : plan.designs)
      std::printf("%s: %s (fidelity %s, %d stages of %g h)%s\n", d.name.c_str(), d.files.front().c_str(),
                  d.scene.fidelity.c_str(), d.scene.wear.stages, d.scene.wear.stage_hours,
                  d.name == plan.reference ? ", reference" : "");
    std::printf("inputs valid; nothing run\n");
    return 0;
  }

  RunContext ctx{args, plan, {}, {}, {}, Clock::now(), 1, {}};
  {
    std::time_t t = std::time(nullptr);
    std::tm tm{};
    localtime_r(&t, &tm);
    char buf[64];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%S%z", &tm);
    ctx.started_text = buf;
  }
  for (std::size_t i = 0; i < plan.designs.size(); ++i) ctx.states.push_back(std::make_unique<DesignState>());
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  ctx.jobs = static_cast<int>(std::min<std::size_t>(args.jobs > 0 ? args.jobs : hw, plan.designs.size()));

  // --resume: the earlier run must have had the same scenes and fidelity.
  const std::string out = args.out;
  std::vector<std::vector<StageRecord>> resume(plan.designs.size());
  bool resuming = false;
  if (args.resume && io::file_exists(resume_key_path(out))) {
    const io::KeyValues have = io::read_key_values(resume_key_path(out));
    for (const auto& d : plan.designs) {
      const std::string was = io::find_value(have, "design." + d.name);
      if (!was.empty() && was != d.fingerprint)
        throw InputError(resume_key_path(out), "design." + d.name,
                         "the same scene and profile files and fidelity as the run being resumed "
                         "(they changed); use a new output folder or drop --resume");
    }
    resuming = true;
  }
  if (resuming) {
    for (std::size_t i = 0; i < plan.designs.size(); ++i) {
      const int k = std::min(io::last_finished_stage(out, plan.designs[i].name), plan.designs[i].scene.wear.stages);
      for (int s = 0; s <= k; ++s) resume[i].push_back(read_stage_state(out, plan.designs[i].name, s));
      ctx.states[i]->resumed_up_to = k;
    }
  }

  // The folder.
  io::create_run_folder(out);
  for (const std::string& dir : {out, io::stages_dir(out), io::profiles_dir(out), io::plots_out_dir(out),
                                 io::plots_data_dir(out), io::join_path(out, "inputs")})
    io::remove_stale_temps(dir);
  if (!resuming) {
    for (const auto& d : plan.designs) {
      remove_stage_state(out, d.name);
      std::error_code ec;
      fs::remove(io::snapshot_path(out, d.name), ec);
      fs::remove(io::liner_path(out, d.name), ec);
    }
    std::error_code ec;
    fs::remove(io::summary_path(out), ec);
    fs::remove(io::spectrum_path(out), ec);
  }
  io::write_file_atomic(resume_key_path(out), io::format_key_values(resume_key(plan), "millwear run inputs (for --resume)"));
  copy_inputs(ctx);

  const bool live = !args.quiet && ::isatty(STDERR_FILENO);
  ProgressView view(ctx, live);
  SignalScope signals;
  g_signal.store(0);

  // Stages read back: the same bookkeeping as freshly finished ones (files rewritten from
  // the exact state, so they match an uninterrupted run).
  for (std::size_t i = 0; i < plan.designs.size(); ++i)
    for (const auto& r : resume[i]) on_stage_done(ctx, i, r);
  {
    std::lock_guard<std::mutex> lock(ctx.mutex);
    write_manifest(ctx, false);
    if (live) {
      std::fprintf(stderr, "millwear run: %zu design(s), %d job(s), fidelity %s, output %s%s\n",
                   plan.designs.size(), ctx.jobs, plan.fidelity.c_str(), out.c_str(),
                   resuming ? " (resumed)" : "");
    }
    view.draw();
  }

  std::atomic<std::size_t> next{0};
  std::atomic<int> running{ctx.jobs};
  std::vector<std::thread> workers;
  for (int j = 0; j < ctx.jobs; ++j)
    workers.emplace_back([&] {
      for (std::size_t i; (i = next.fetch_add(1)) < plan.designs.size();) {
        if (g_signal.load() != 0) {
          std::lock_guard<std::mutex> lock(ctx.mutex);
          ctx.states[i]->status = Status::Interrupted;
          continue;
        }
        run_design(ctx, i, resume[i]);
      }
      running.fetch_sub(1);
    });
  while (running.load() > 0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    std::lock_guard<std::mutex> lock(ctx.mutex);
    view.draw();
  }
  for (auto& w : workers) w.join();
  {
    std::lock_guard<std::mutex> lock(ctx.mutex);
    view.draw();
  }

  bool failed = false, interrupted = false;
  for (const auto& st : ctx.states) {
    failed = failed || st->status == Status::Failed;
    interrupted = interrupted || st->status == Status::Interrupted;
  }
  const double wall = std::chrono::duration<double>(Clock::now() - ctx.t0).count();
  {
    std::lock_guard<std::mutex> lock(ctx.mutex);
    write_summary(ctx);
    write_manifest(ctx, !interrupted);
  }

  if (interrupted) {
    const int sig = g_signal.load();
    print_final_summary(ctx, wall);
    std::fprintf(stderr,
                 "millwear: interrupted%s; finished stages are kept in %s. Run the same command "
                 "with --resume to continue.\n",
                 sig == 0 ? " (--stop-after-stage)" : sig == SIGTERM ? " by SIGTERM" : " by SIGINT",
                 out.c_str());
    return sig == SIGTERM ? 128 + SIGTERM : 128 + SIGINT;
  }

  // Figures from whatever finished.
  bool figures_failed = false;
  std::vector<std::string> names;
  for (const auto& d : plan.designs) names.push_back(d.name);
  try {
    plots::render_all_figures(out, names, plan.reference);
  } catch (const std::exception& e) {
    if (plots::gnuplot_available()) figures_failed = true;
    std::fprintf(stderr, "millwear: warning: figures: %s\n", e.what());
  }

  print_final_summary(ctx, wall);
  std::printf("results in %s (summary.csv, manifest.json, profiles/); figures in %s\n", out.c_str(),
              io::plots_out_dir(out).c_str());
  for (std::size_t i = 0; i < plan.designs.size(); ++i)
    if (ctx.states[i]->status == Status::Failed)
      std::fprintf(stderr, "millwear: run failed: %s: %s (finished stages are kept; --resume retries)\n",
                   plan.designs[i].name.c_str(), ctx.states[i]->error.c_str());
  return failed || figures_failed ? 1 : 0;
}

void register_run(CLI::App& app, Action* action) {
  auto args = std::make_shared<RunArgs>();
  CLI::App* cmd = app.add_subcommand(
      "run",
      "Run the wear history of one or more designs and compare them: summary.csv, lifter "
      "profiles per stage, figures (paper Figs 6-10), resumable");
  cmd->footer(
      "A SCENE is a scene file (one design, named by its `name`) or a comparison file:\n"
      "  [comparison]\n"
      "  designs = [\"sag-2x30.toml\", \"sag-1x30.toml\"]   # relative to the comparison file\n"
      "  reference = \"sag-1x30\"   # its new stage normalises the *_norm columns (default: first)\n"
      "Units: hours, mm, mm^2, kW per mill (per-metre figure x mill length).\n"
      "Exit codes: 0 done, 1 a design or figure failed (the others finish), 2 bad input,\n"
      "130/143 interrupted (Ctrl-C/SIGTERM): finished stages are kept, --resume continues.");
  cmd->add_option("scene", args->scenes, "scene or comparison files (TOML)")->required();
  cmd->add_option("-o,--out", args->out, "output folder")->required();
  cmd->add_option("--fidelity", args->fidelity, "draft | standard | reference (default: each scene's)");
  cmd->add_option("--reference", args->reference, "design whose new stage normalises (default: the comparison's, else the first)");
  cmd->add_flag("--resume", args->resume, "continue an interrupted run in OUT from its last finished stages");
  cmd->add_flag("-q,--quiet", args->quiet, "no live progress, only the final summary");
  cmd->add_flag("--check", args->check, "validate the scenes and comparison files, list the designs, run nothing");
  cmd->add_option("-j,--jobs", args->jobs, "designs run at once (default: hardware cores)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--stop-after-stage", args->stop_after_stage,
                  "for testing: stop cleanly after stage K as if interrupted (then --resume)")
      ->check(CLI::NonNegativeNumber);
  cmd->callback([args, action] { *action = [args] { return run_command(*args); }; });
}

}  // namespace millwear::app
