// The live mill behind `millwear view` (see live_mill.hpp): controls through the scene
// checker, the live charge in batches, the wear mode on its own thread.
#include "view/live_mill.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/errors.hpp"
#include "common/units.hpp"
#include "io/atomic_write.hpp"
#include "io/run_folder.hpp"
#include "metrics/batch_means.hpp"
#include "scene/fidelity.hpp"
#include "scene/limits.hpp"
#include "study/charge_run.hpp"
#include "study/stage_files.hpp"
#include "view/charge_edit.hpp"
#include "wear/history.hpp"
#include "wear/reshape.hpp"
#include "wear/window.hpp"

namespace millwear::view {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kReadoutsKept = 240;  // batches in the rolling plot
constexpr std::size_t kTrailPoints = 180;   // frames a trail keeps (3 s at 60 frames/s)
// The first lines of the files a scene save writes, the scene's and the lifter's beside it: a
// file of their name without it is not the view's to replace (own_files.hpp).
constexpr const char* kSavedSceneMark = "# Scene saved by millwear view";
constexpr const char* kSavedLifterMark = "# Lifter saved by millwear view";

std::string number(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

std::string read_text(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw InputError(path, "", "scene file not found or not a regular file");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string dir_of(const std::string& file) {
  const fs::path p = fs::absolute(fs::path(file)).parent_path();
  return p.string();
}

}  // namespace

LiveMill::LiveMill(const std::string& scene_file, const std::string& fidelity)
    : scene_file_(scene_file), fidelity_(fidelity), text_(read_text(scene_file)) {
  scene_ = checked_scene({});
  new_mill_ = build_scene_mill(scene_);
  mill_ = new_mill_;
  start_engine(fill_charge(scene_, mill_));
  phase_ = Phase::Settling;
  phase_end_s_ = engine_->state().time_s + scene_.solver.settle_time_s;
  changed();
}

LiveMill::~LiveMill() {
  stop_wear();
  if (!temp_dir_.empty()) {
    std::error_code ec;
    fs::remove_all(temp_dir_, ec);
  }
}

Scene LiveMill::checked_scene(const std::vector<KeyEdit>& edits) const {
  const std::string text = edits.empty() ? text_ : edited_scene_text(text_, scene_file_, edits, dir_of(scene_file_), "");
  Scene s = load_scene_text(text, scene_file_);
  if (!fidelity_.empty()) apply_fidelity(s, fidelity_);
  check_run_limits(s, scene_file_);
  return s;
}

std::vector<KeyEdit> LiveMill::edits_with(const KeyEdit& e) const {
  std::map<std::string, KeyEdit> all = edits_;
  all[e.table + "." + e.key] = e;
  std::vector<KeyEdit> v;
  for (auto& [k, edit] : all) v.push_back(edit);
  return v;
}

double LiveMill::signed_speed_rad_s() const {
  const double sign = direction_at(scene_, 0.0);
  return phase_ == Phase::Settling ? 0.0 : sign * scene_.angular_speed_rad_s();
}

void LiveMill::start_engine(const ChargeState& charge) {
  engine_ = make_engine(scene_, mill_, charge, accounting_options_for(scene_));
  engine_->set_mill_speed(signed_speed_rad_s());
  engine_->reset_window();
  events_seen_ = 0;
  trail_ids_.clear();
  trails_.clear();
}

std::size_t LiveMill::active_disks() const {
  const ChargeState& s = engine_->state();
  return static_cast<std::size_t>(std::count(s.active.begin(), s.active.end(), std::uint8_t{1}));
}

// A control changed the mill: the readouts start a new steady window once the charge has
// turned for the scene's spin-up (at least one revolution) at the new setting.
void LiveMill::changed() {
  steady_batches_.clear();
  steady_from_s_ = clock_s_ + std::max(1.0, scene_.solver.spinup_revolutions) * scene_.revolution_time_s();
  batch_s_ = 0.5 * scene_.revolution_time_s();
  batch_elapsed_s_ = 0.0;
  engine_->reset_window();
}

std::string LiveMill::apply(const KeyEdit& e, bool rebuild_mill, bool refill) {
  if (wear_running()) return "the wear mode is running: stop it first";
  std::vector<KeyEdit> edits = edits_with(e);
  try {
    Scene s = checked_scene(edits);
    MillGeometry m = rebuild_mill ? build_scene_mill(s) : mill_;
    ChargeState charge;
    if (rebuild_mill) charge = fit_charge_to_liner(s, m, engine_->state());
    else if (refill) charge = refill_charge(s, m, engine_->state());
    edits_[e.table + "." + e.key] = e;
    scene_ = std::move(s);
    if (rebuild_mill) {
      mill_ = m;
      new_mill_ = std::move(m);
    }
    if (rebuild_mill || refill) start_engine(charge);
    else engine_->set_mill_speed(signed_speed_rad_s());
  } catch (const InputError& x) {
    return x.what();
  } catch (const RunError& x) {
    return x.what();
  }
  changed();
  return "";
}

std::string LiveMill::set_speed(double f) { return apply({"mill", "speed", number(f), {"speed_rpm"}}, false, false); }

std::string LiveMill::set_filling(double filling, double ball_filling) {
  // Both keys in one change: the checker sees the pair (ball filling is part of filling).
  const auto saved = edits_;
  edits_["charge.ball_filling"] = {"charge", "ball_filling", number(ball_filling), {}};
  const std::string r = apply({"charge", "filling", number(filling), {}}, false, true);
  if (!r.empty()) edits_ = saved;
  return r;
}

std::string LiveMill::set_direction(bool reverse) {
  // A one-way mill: the reversal period belongs to bidirectional mills only.
  const auto saved = edits_;
  edits_["mill.reverse_every"] = {"mill", "reverse_every", "", {}};
  const std::string r = apply({"mill", "direction", reverse ? "\"reverse\"" : "\"forward\"", {}}, false, false);
  if (!r.empty()) edits_ = saved;
  return r;
}

std::string LiveMill::set_profile(const std::string& file) {
  const std::string abs = fs::absolute(fs::path(file)).lexically_normal().string();
  // One profile for every row: on a scene with a pattern of kinds it takes the pattern's place.
  const std::string r = apply({"lifters", "profile", toml_string_value(abs), {"pattern"}}, true, false);
  if (r.empty()) edited_profile_text_.clear();
  return r;
}

std::string LiveMill::set_lifter_shape(double height_mm, double leading_deg, double trailing_deg) {
  if (!lifter_is_trapezoid()) return "the lifter profile is a polyline: its height and face angles are not parameters";
  if (temp_dir_.empty()) {
    temp_dir_ = (fs::temp_directory_path() / ("millwear-view-" + std::to_string(::getpid()))).string();
    fs::create_directories(temp_dir_);
  }
  const TrapezoidDef& t = scene_.mill.lifter.trapezoid;
  std::string text = "name = \"" + scene_.mill.lifter.name + "-edited\"\nform = \"trapezoid\"\n";
  text += "height = " + number(height_mm) + "\ntop_width = " + number(in_mm(t.top_width_m)) + "\n";
  text += "leading_face_angle = " + number(leading_deg) + "\ntrailing_face_angle = " + number(trailing_deg) + "\n";
  const std::string file = (fs::path(temp_dir_) / (scene_.name + "_lifter.toml")).string();
  const std::string before = fs::exists(file) ? read_text(file) : "";
  io::write_file_atomic(file, text);
  std::string r = apply({"lifters", "profile", toml_string_value(file), {"pattern"}}, true, false);
  if (r.empty()) {
    edited_profile_text_ = text;
    return r;
  }
  if (!before.empty()) io::write_file_atomic(file, before);  // the lifter in use stays
  // Said of the lifter asked for, by its three values: the file it went into is the view's
  // own, and the scene's profile line that names that file is no value the user gave.
  const std::string asked = "lifter " + number(height_mm) + " " + number(leading_deg) + " " + number(trailing_deg);
  if (const auto at = r.find(file); at != std::string::npos) r.replace(at, file.size(), asked);
  const auto named = r.rfind(" (the profile named by lifters.profile in ");
  if (named != std::string::npos && r.back() == ')') r.erase(named);
  return r;
}

bool LiveMill::lifter_is_trapezoid() const { return scene_.mill.lifter.form == ProfileForm::Trapezoid; }
std::string LiveMill::profile_file() const { return scene_.mill.lifter.source_file; }
double LiveMill::lifter_height_mm() const { return in_mm(scene_.mill.lifter.trapezoid.height_m); }
double LiveMill::leading_face_deg() const { return deg_from_rad(scene_.mill.lifter.trapezoid.leading_face_angle_rad); }
double LiveMill::trailing_face_deg() const { return deg_from_rad(scene_.mill.lifter.trapezoid.trailing_face_angle_rad); }

std::string LiveMill::reset() {
  if (wear_running()) return "the wear mode is running: stop it first";
  mill_ = new_mill_;
  start_engine(fill_charge(scene_, mill_));
  phase_ = Phase::Settling;
  engine_->set_mill_speed(0.0);
  phase_end_s_ = engine_->state().time_s + scene_.solver.settle_time_s;
  readouts_.clear();
  edge_shear_.clear();
  changed();
  return "";
}

void LiveMill::close_batch() {
  const Accounting& acc = engine_->accounting();
  const ChargeFigures f = charge_figures(acc, scene_, signed_speed_rad_s());
  Readout r;
  r.clock_s = clock_s_;
  r.summary = f.summary;
  r.power_kW_per_m = f.power_kW_per_m;
  r.power_kW_per_mill = f.power_kW_per_m * scene_.mill.length_m;
  const double tonnes_per_m = f.summary.mass_kg / scene_.slice_thickness() / 1000.0;
  r.power_kW_per_t = tonnes_per_m > 0 ? f.power_kW_per_m / tonnes_per_m : 0.0;
  r.collision_kW_per_m = f.collision_kW_per_m;
  r.utilisation = f.power_kW_per_m > 0 ? f.collision_kW_per_m / f.power_kW_per_m : 0.0;
  r.liner_shear_kW_per_m = in_kW(f.summary.shear_work_rate_W) / scene_.slice_thickness();
  r.toe_deg = f.summary.toe_deg;
  r.shoulder_deg = f.summary.shoulder_deg;
  r.centrifuged = f.summary.centrifuged;
  r.centre_of_mass_m = f.summary.centre_of_mass_m;
  readouts_.push_back(r);
  if (readouts_.size() > kReadoutsKept) readouts_.pop_front();
  // A batch counts toward the steady mean when it began after the change's spin-up: one that
  // ended after it but began before holds part of the transient.
  if (clock_s_ - batch_elapsed_s_ >= steady_from_s_ - 1e-9) steady_batches_.push_back(r.power_kW_per_m);
  // Liner colour: shear power per unit area, averaged over the last few batches.
  const double t = scene_.slice_thickness();
  const bool fresh = edge_shear_.size() != acc.shear_work_J.size();
  edge_shear_.resize(acc.shear_work_J.size(), 0.0);
  for (std::size_t e = 0; e < edge_shear_.size() && e < mill_.edge_length_m.size(); ++e) {
    const double w = acc.time_s > 0 ? acc.shear_work_J[e] / acc.time_s / (mill_.edge_length_m[e] * t) : 0.0;
    edge_shear_[e] = fresh ? w : 0.7 * edge_shear_[e] + 0.3 * w;
  }
  engine_->reset_window();
  batch_elapsed_s_ = 0.0;
}

void LiveMill::advance(double simulated_s) {
  take_wear_result();
  if (paused_ || wear_running()) return;
  step_frame(simulated_s * time_scale_);
}

void LiveMill::step_frame(double simulated_s) {
  if (wear_running()) return;
  const double dt = engine_->time_step_s();
  double owed = simulated_s + step_debt_s_;
  std::int64_t n = static_cast<std::int64_t>(std::floor(owed / dt + 1e-9));
  step_debt_s_ = std::max(0.0, owed - static_cast<double>(n) * dt);
  while (n > 0) {
    std::int64_t k = n;
    if (phase_ == Phase::Settling) {
      k = std::min<std::int64_t>(k, std::max<std::int64_t>(1, steps_for(phase_end_s_ - engine_->state().time_s, dt)));
    } else {
      k = std::min<std::int64_t>(k, std::max<std::int64_t>(1, steps_for(batch_s_ - batch_elapsed_s_, dt)));
    }
    engine_->step(static_cast<int>(k));
    n -= k;
    clock_s_ += static_cast<double>(k) * dt;
    disk_steps_ += k * static_cast<std::int64_t>(engine_->state().size());
    if (phase_ == Phase::Settling) {
      if (engine_->state().time_s >= phase_end_s_ - 1e-9) {
        phase_ = Phase::Turning;
        engine_->set_mill_speed(signed_speed_rad_s());
        changed();
      }
    } else {
      batch_elapsed_s_ += static_cast<double>(k) * dt;
      if (batch_elapsed_s_ >= batch_s_ - 1e-9) close_batch();
    }
  }
  const auto& ev = engine_->events();
  for (; events_seen_ < ev.size(); ++events_seen_) events_.push_back(ev[events_seen_].what);
  lost_ = 0;
  for (std::uint8_t a : engine_->state().active) lost_ += a ? 0 : 1;
  record_trails();
}

SteadyPower LiveMill::steady_power() const {
  SteadyPower p;
  p.batches = static_cast<int>(steady_batches_.size());
  const BatchMeans b = batch_means(steady_batches_);
  // One batch has no spread to give an error by; none, no mean.
  p.mean_kW_per_m = p.batches > 0 ? b.mean : std::nan("");
  p.sem_kW_per_m = p.batches > 1 ? b.sem : std::nan("");
  return p;
}

void LiveMill::set_trail_count(int n) {
  trail_count_ = std::clamp(n, 0, 32);
  trail_ids_.clear();
  trails_.clear();
}

void LiveMill::record_trails() {
  const ChargeState& s = engine_->state();
  if (trail_ids_.empty() && trail_count_ > 0 && s.size() > 0) {
    // Spread through the disk list (the fill places them largest first, bottom to top).
    for (int j = 0; j < trail_count_; ++j)
      trail_ids_.push_back(static_cast<int>((2 * j + 1) * s.size() / (2 * static_cast<std::size_t>(trail_count_))));
    trails_.assign(trail_ids_.size(), {});
  }
  for (std::size_t j = 0; j < trail_ids_.size(); ++j) {
    const int id = trail_ids_[j];
    if (!s.active[static_cast<std::size_t>(id)]) continue;
    trails_[j].push_back(s.position_m[static_cast<std::size_t>(id)]);
    if (trails_[j].size() > kTrailPoints) trails_[j].pop_front();
  }
}

std::vector<std::string> LiveMill::save_scene(const std::string& file, const std::vector<RunInput>& inputs) const {
  std::vector<std::string> written;
  const fs::path target = fs::absolute(fs::path(file)).lexically_normal();
  const std::string out_dir = target.parent_path().string();
  std::vector<RunInput> kept = inputs;
  kept.push_back({scene_file_, "the scene on screen"});
  if (const std::string r = overwrite_refusal(target.string(), kSavedSceneMark, 0,
                                              "its first line is not \"" + std::string(kSavedSceneMark) + " ...\"", kept);
      !r.empty())
    throw InputError(file, "", "a free name for the saved scene, or a scene millwear view saved there: " + r +
                                   "; save the scene under another name");
  std::string lifter_file;
  if (!edited_profile_text_.empty()) {
    lifter_file = (target.parent_path() / (target.stem().string() + "_lifter.toml")).string();
    if (const std::string r = overwrite_refusal(lifter_file, kSavedLifterMark, 0,
                                                "its first line is not \"" + std::string(kSavedLifterMark) + " ...\"", kept);
        !r.empty())
      throw InputError(lifter_file, "",
                       "a name free for the edited lifter of " + target.filename().string() +
                           " (a scene save writes its lifter as FILE_lifter.toml), or a lifter a scene save wrote: " + r +
                           "; save the scene under another name, or move that file");
  }
  std::vector<KeyEdit> edits;
  for (const auto& [k, e] : edits_) edits.push_back(e);
  if (!fidelity_.empty()) edits.push_back({"", "fidelity", "\"" + fidelity_ + "\"", {}});
  // The header goes in as the mark's text: edited_scene_text writes it after "# ".
  const std::string header = std::string(kSavedSceneMark).substr(2) + " from " + scene_file_;
  // What is written reads back as the scene on screen: the checker reads it from the folder it
  // goes to before anything is written (the folder neither). An edited lifter is read from the
  // view's own file of it, which the one written beside the scene repeats below its mark.
  const std::string checked = edited_scene_text(text_, scene_file_, edits, out_dir, header);
  Scene check = load_scene_text(checked, target.string());
  check_run_limits(check, target.string());
  std::string text = checked;
  if (!lifter_file.empty()) {
    for (auto& e : edits)
      if (e.table == "lifters" && e.key == "profile") e.value = toml_string_value(target.stem().string() + "_lifter.toml");
    text = edited_scene_text(text_, scene_file_, edits, out_dir, header);
  }
  io::ensure_dir(out_dir);  // `save_scene out/lab-edited.toml` makes out/, as a recording does
  if (!lifter_file.empty()) {
    io::write_file_atomic(lifter_file, std::string(kSavedLifterMark) + " with " + target.filename().string() + "\n" +
                                           edited_profile_text_);
    written.push_back(lifter_file);
  }
  io::write_file_atomic(target.string(), text);
  written.push_back(target.string());
  return written;
}

// --- wear mode -------------------------------------------------------------------------

bool LiveMill::wear_running() const {
  std::lock_guard<std::mutex> lock(wear_mutex_);
  return wear_.running;
}

std::string LiveMill::start_wear(double hours) {
  if (wear_running()) return "the wear mode is running already";
  if (wear_thread_.joinable()) wear_thread_.join();
  Scene ws = scene_;
  if (!(hours > 0.0)) return "wear hours: expected a positive number of operating hours";
  ws.wear.stages = stages_to_reach(hours, ws.wear.stage_hours);
  try {
    check_scene(ws, scene_file_);
  } catch (const InputError& x) {
    return x.what();
  }
  const double new_area = measure_lifter(new_mill_.units[0], new_mill_.radius_m).area_m2;
  {
    std::lock_guard<std::mutex> lock(wear_mutex_);
    wear_ = WearView{};
    wear_.running = true;
    wear_.target_hours = ws.wear.stages * ws.wear.stage_hours;
    wear_.mill = new_mill_;
    wear_.charge = engine_->state();
  }
  wear_records_.clear();
  wear_scene_ = ws;
  wear_stop_ = false;
  wear_taken_ = false;
  wear_thread_ = std::thread([this, ws, new_area] {
    WearCallbacks cb;
    auto show = [this, new_area](int stage, double hours, const MillGeometry& mill, const ChargeState* charge) {
      std::lock_guard<std::mutex> lock(wear_mutex_);
      wear_.stage = stage;
      wear_.hours = hours;
      wear_.mill = mill;
      if (charge) wear_.charge = *charge;
      const double a = measure_lifter(mill.units[0], mill.radius_m).area_m2;
      wear_.area_lost_share = new_area > 0 ? 1.0 - a / new_area : 0.0;
      ++wear_.version;
    };
    cb.on_update = [show](const WearUpdate& u) { show(u.stage, u.hours, *u.mill, u.charge); };
    cb.on_stage = [this, show](const StageRecord& rec) {
      {
        std::lock_guard<std::mutex> lock(wear_mutex_);
        wear_records_.push_back(rec);
      }
      if (rec.units.empty()) return;
      const MillGeometry m = build_mill(new_mill_.radius_m, new_mill_.rows, rec.units, new_mill_.kinds);
      show(rec.stage, rec.hours, m, rec.snapshot.size() ? &rec.snapshot : nullptr);
    };
    cb.should_stop = [this] { return wear_stop_.load(); };
    std::string message;
    try {
      const WearHistory h = run_wear_history(ws, cb);
      message = h.failure.empty() ? (h.events.empty() ? "" : h.events.back()) : h.failure;
    } catch (const std::exception& x) {
      message = x.what();
    }
    std::lock_guard<std::mutex> lock(wear_mutex_);
    wear_.message = message;
    wear_.running = false;
    wear_.finished = true;
    ++wear_.version;
  });
  return "";
}

void LiveMill::stop_wear() {
  wear_stop_ = true;
  if (wear_thread_.joinable()) wear_thread_.join();
}

void LiveMill::wait_wear() {
  if (wear_thread_.joinable()) wear_thread_.join();
}

WearView LiveMill::wear_view() const {
  std::lock_guard<std::mutex> lock(wear_mutex_);
  return wear_;
}

// Once the wear thread has ended, the live charge carries on in the worn mill.
void LiveMill::take_wear_result() {
  if (wear_taken_) return;
  WearView w;
  {
    std::lock_guard<std::mutex> lock(wear_mutex_);
    if (wear_.running) return;
    w = wear_;
  }
  if (wear_thread_.joinable()) wear_thread_.join();
  wear_taken_ = true;
  if (w.mill.boundary.empty()) return;
  mill_ = w.mill;
  try {
    start_engine(fit_charge_to_liner(scene_, mill_, engine_->state()));
  } catch (const RunError& x) {
    std::lock_guard<std::mutex> lock(wear_mutex_);
    wear_.message = x.what();
  }
  edge_shear_.clear();
  changed();
}

void LiveMill::write_wear_profiles(const std::string& out) const {
  std::lock_guard<std::mutex> lock(wear_mutex_);
  if (wear_records_.empty() || wear_.running) throw RunError("no finished wear history to write");
  // A command's results folder (a run's, whose profiles these would replace) is not the view's
  // to write into; elsewhere a profile file already there is replaced only by the same text
  // (this history saved again), never by another history's.
  std::error_code ec;
  if (fs::is_directory(out, ec))
    if (const std::string holder = io::folder_results_command(out); !holder.empty())
      throw InputError(out, "", "a folder of no millwear command's results, but it holds those of `millwear " + holder +
                                    "`, whose files the wear history's profiles would replace: save them into another folder");
  for (const StageRecord& rec : wear_records_) {
    const std::string path = io::profile_path(out, scene_.name, rec.stage);
    if (fs::exists(fs::symlink_status(path, ec)) && read_text(path) != study::profile_csv_text(rec))
      throw InputError(path, "", "a name free for the wear history's stage " + std::to_string(rec.stage) +
                                     " profile: a file of other points is there, which it would replace; save the "
                                     "profiles into another folder, or move that file");
  }
  for (const StageRecord& rec : wear_records_) study::write_profile_csv(out, scene_.name, rec);
}

}  // namespace millwear::view
