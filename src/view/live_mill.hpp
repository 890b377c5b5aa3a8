#pragma once
// The live mill behind `millwear view`, without any window: the scene as the controls have
// edited it, the engine turning its charge (the scene's backend: the soft one in every
// preset), the readouts of the last measuring batches, the trails of a few disks, and the wear
// mode (the scene's wear history as `millwear run` computes it, on its own thread so the
// window keeps drawing). The window (view/window.cpp) reads it and
// calls its controls; a script of timed control changes calls the same functions.
//
// Every control edits the scene's text (scene/scene_edit.hpp) and reads it back through the
// scene checker (load_scene_text, then check_run_limits): a value the checker refuses is
// refused with its message and nothing changes; the saved scene is that same text.
#include <atomic>
#include <cstdint>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "engine/engine.hpp"
#include "metrics/charge_summary.hpp"
#include "scene/scene.hpp"
#include "scene/scene_edit.hpp"
#include "view/own_files.hpp"
#include "wear/history.hpp"

namespace millwear::view {

// What one measuring batch (half a revolution) of the live charge gave.
struct Readout {
  double clock_s = 0.0;              // view time at the batch's end
  double power_kW_per_m = 0.0;       // drive power per metre of mill
  double power_kW_per_mill = 0.0;    // times the mill length
  double power_kW_per_t = 0.0;       // per tonne of charge
  double collision_kW_per_m = 0.0;
  double utilisation = 0.0;          // collision power / drive power
  double liner_shear_kW_per_m = 0.0; // shear work rate on the whole liner
  double toe_deg = 0.0, shoulder_deg = 0.0;  // from 6 o'clock, + on the rising side
  bool centrifuged = false;          // no toe or shoulder: the charge rides round the shell
  Vec2 centre_of_mass_m;
  ChargeSummary summary;             // the batch's whole summary (per slice, SI)
};

// The mean of the batches since the last change, once the charge has turned for a
// revolution after it (the change's transient is left out). NaN for what is not measured yet.
struct SteadyPower {
  int batches = 0;
  double mean_kW_per_m = 0.0;        // NaN before the first batch
  double sem_kW_per_m = 0.0;         // batch-means standard error (NaN under two batches)
};

// The wear mode as the window draws it.
struct WearView {
  bool running = false, finished = false;
  int stage = 0;
  double hours = 0.0;
  double target_hours = 0.0;
  double area_lost_share = 0.0;      // of the new lifter's area
  MillGeometry mill;                 // the liner now (valid when hours > 0 or finished)
  ChargeState charge;                // the charge the wear loop turns
  std::string message;               // failure or event text
  std::uint64_t version = 0;         // bumps at every update
};

enum class Phase { Settling, Turning };

class LiveMill {
 public:
  // Reads and checks the scene (InputError as `millwear charge` would throw), fills the mill.
  LiveMill(const std::string& scene_file, const std::string& fidelity);
  ~LiveMill();
  LiveMill(const LiveMill&) = delete;
  LiveMill& operator=(const LiveMill&) = delete;

  // Controls. Each returns "" when the change took effect, else the scene checker's message
  // (or the reason it cannot be done) and nothing changed.
  std::string set_speed(double fraction_of_critical);
  std::string set_filling(double filling, double ball_filling);
  std::string set_direction(bool reverse);
  std::string set_profile(const std::string& profile_file);
  std::string set_lifter_shape(double height_mm, double leading_deg, double trailing_deg);
  void set_paused(bool paused) { paused_ = paused; }
  void set_time_scale(double s) { time_scale_ = s; }
  // A fresh fill of the scene as it stands, settled again; refused (the reason) while the
  // wear mode runs.
  std::string reset();
  void step_frame(double simulated_s);  // one frame even when paused

  // Advance the live charge by simulated_s (times the time scale; nothing when paused or
  // while the wear mode runs).
  void advance(double simulated_s);

  // Wear mode: the scene's staged wear history (wear.stages raised to cover `hours`) on a
  // thread; the view draws its liner and charge after every update. "" or why not.
  std::string start_wear(double hours);
  void stop_wear();
  void wait_wear();         // until the wear thread ends
  WearView wear_view() const;
  bool wear_running() const;
  // The profile files `millwear run` writes (OUT/profiles/DESIGN_stageK.csv) for the last
  // finished wear history, into `out`. Throws RunError when no history has finished, and
  // InputError, writing nothing, for a folder of a command's results (a run's) or a profile
  // file there of other points.
  void write_wear_profiles(const std::string& out) const;

  // The scene as edited, as a TOML file `millwear run` accepts, its first line marking it as
  // the view's (an edited lifter goes beside it as FILE_lifter.toml, marked too). A file of
  // either name without the mark, the scene on screen or one of `inputs` (the script) is
  // refused, InputError, and nothing is written. Written atomically. Returns the files written.
  std::vector<std::string> save_scene(const std::string& file, const std::vector<RunInput>& inputs = {}) const;

  const Scene& scene() const { return scene_; }
  const MillGeometry& mill() const { return mill_; }
  const MillGeometry& new_mill() const { return new_mill_; }
  const ChargeState& charge() const { return engine_->state(); }
  Phase phase() const { return phase_; }
  bool paused() const { return paused_; }
  double time_scale() const { return time_scale_; }
  double clock_s() const { return clock_s_; }
  double signed_speed_rad_s() const;
  const std::deque<Readout>& readouts() const { return readouts_; }
  SteadyPower steady_power() const;
  // Shear power per unit liner area of each mill edge over the last batches, W/m^2.
  const std::vector<double>& edge_shear_W_m2() const { return edge_shear_; }
  // Disks lost (escaped or non-finite) since the live began, and the engine's events.
  std::size_t lost_disks() const { return lost_; }
  const std::vector<std::string>& events() const { return events_; }
  std::size_t active_disks() const;
  // Trails: the last positions of a few disks spread through the charge (world frame).
  void set_trail_count(int n);
  const std::vector<std::deque<Vec2>>& trails() const { return trails_; }
  // Lifter shape controls: the profile's trapezoid (false for a polyline profile).
  bool lifter_is_trapezoid() const;
  std::string profile_file() const;
  double leading_face_deg() const;
  double trailing_face_deg() const;
  double lifter_height_mm() const;
  std::int64_t disk_steps() const { return disk_steps_; }

 private:
  // The edited scene, checked; throws InputError with the checker's message.
  Scene checked_scene(const std::vector<KeyEdit>& edits) const;
  std::vector<KeyEdit> edits_with(const KeyEdit& e) const;
  std::string apply(const KeyEdit& e, bool rebuild_mill, bool refill);
  void start_engine(const ChargeState& charge);
  void close_batch();
  void changed();
  void record_trails();
  void take_wear_result();

  std::string scene_file_, fidelity_, text_;
  std::map<std::string, KeyEdit> edits_;       // by "table.key"
  std::string edited_profile_text_;            // the lifter as the shape controls made it
  std::string temp_dir_;                        // where that profile file lives
  Scene scene_;
  MillGeometry mill_, new_mill_;
  std::unique_ptr<Engine> engine_;
  Phase phase_ = Phase::Settling;
  double phase_end_s_ = 0.0;       // engine time the settling ends
  bool paused_ = false;
  double time_scale_ = 1.0;
  double clock_s_ = 0.0;           // view time, never reset
  double step_debt_s_ = 0.0;       // simulated time owed to the next frame (below one step)
  double batch_s_ = 0.0, batch_elapsed_s_ = 0.0;
  double steady_from_s_ = 0.0;     // clock time the steady window starts (after a transient)
  std::deque<Readout> readouts_;
  std::vector<double> steady_batches_;
  std::vector<double> edge_shear_;
  std::size_t lost_ = 0;
  std::size_t events_seen_ = 0;
  std::vector<std::string> events_;
  std::int64_t disk_steps_ = 0;
  int trail_count_ = 4;
  std::vector<int> trail_ids_;
  std::vector<std::deque<Vec2>> trails_;

  // Wear mode.
  std::thread wear_thread_;
  std::atomic<bool> wear_stop_{false};
  mutable std::mutex wear_mutex_;
  WearView wear_;
  std::vector<StageRecord> wear_records_;
  Scene wear_scene_;
  bool wear_taken_ = true;
};

}  // namespace millwear::view
