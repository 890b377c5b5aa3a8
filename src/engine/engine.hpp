#pragma once
// The charge on a contact solver. One interface, two backends (engine/box2d/ wraps the Box2D
// library; engine/soft/ is our own disk solver). Both feed ContactRecords to the shared
// accounting, so their outputs compare line by line. Virtual calls happen per step, never
// per contact.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "engine/accounting.hpp"
#include "engine/charge.hpp"
#include "mill/mill.hpp"
#include "scene/scene.hpp"

namespace millwear {

// Something the engine noticed and the caller must hear about (escaped disk, NaN).
struct EngineEvent {
  double time_s = 0.0;
  std::string what;
};

class Engine {
 public:
  virtual ~Engine() = default;
  // Replace the liner (after a wear update). Disks keep their state.
  virtual void set_liner(const MillGeometry& mill) = 0;
  // Signed mill speed, rad/s (+ counter-clockwise = forward).
  virtual void set_mill_speed(double omega_rad_s) = 0;
  // Advance n steps of the scene's time step, accounting every contact.
  virtual void step(int n) = 0;
  virtual const ChargeState& state() const = 0;
  virtual double time_step_s() const = 0;
  virtual const char* backend_name() const = 0;

  // Start a new measuring window: zero the sums, remember the charge's energy now.
  void reset_window();

  Accounting& accounting() { return accounting_; }
  const Accounting& accounting() const { return accounting_; }
  const std::vector<EngineEvent>& events() const { return events_; }
  // Wall-clock seconds spent in each part of step(), for benchmarks.
  // collide_s is the narrow phase (pair tests, liner tests, contact matching); broad_s the
  // broad phase where a backend can time it apart (the soft backend's grid; Box2D: 0).
  struct Timing {
    double collide_s = 0, solve_s = 0, account_s = 0;
    std::int64_t disk_steps = 0;
    double broad_s = 0;
    // Contact rows summed over steps (soft backend; the library leaves them 0): every
    // candidate disk pair, the pairs carrying an impulse into the step, the liner rows.
    // Per disk-step they tell whether a cost per disk-step grows with the work or without it.
    std::int64_t pair_rows = 0, live_pair_rows = 0, liner_rows = 0;
  };
  const Timing& timing() const { return timing_; }

 protected:
  Accounting accounting_;
  std::vector<EngineEvent> events_;
  Timing timing_;
  std::size_t edge_count_ = 0;
};

// Kinetic (translation + rotation) and potential energy of the active charge, J.
double charge_kinetic_J(const ChargeState& s);
double charge_potential_J(const ChargeState& s, double gravity_m_s2);

// Place non-overlapping disks to the scene's filling and size distribution, with its seed,
// in the lower part of the mill (mill at rest). Deterministic.
ChargeState fill_charge(const Scene& scene, const MillGeometry& mill);

std::unique_ptr<Engine> make_engine(const Scene& scene, const MillGeometry& mill,
                                    const ChargeState& initial, const AccountingOptions& opts);

// Accounting options a scene asks for (a scene pays only for what it uses).
AccountingOptions accounting_options_for(const Scene& scene);

// A disk is lost to the liner when its centre is this many radii past the liner surface
// (the soft backend's face contacts keep working to half a radius past the face line,
// soft/liner_lookup.hpp) or as far past the farthest liner point; both backends remove it
// and report it.
constexpr double kLostDepthRadii = 0.5;
// Both backends look for disks leaked into the liner every this many steps. The check walks
// a lifter surface for every disk in the liner band, about what the liner search costs; a
// disk that deep stays there, so finding it up to 16 steps late changes only the step in
// which it is removed.
constexpr int kInsideLinerCheckInterval = 16;

// A phase's steps between two calls of its stop check, in disk-steps: a quarter to half a
// second of one core at any charge size, so a stop asked for in the settling of a million
// disks is heard as soon as in a window of a thousand.
constexpr std::int64_t kStopCheckDiskSteps = std::int64_t{1} << 20;

// Advance n steps in pieces of at most kStopCheckDiskSteps disk-steps (at least one step),
// calling check_stop before each piece (no check_stop: one piece); check_stop stops the phase
// by throwing. The same steps, and bits, as engine.step(n).
void step_checking_stop(Engine& engine, int n, const std::function<void()>& check_stop);

// Settle the charge at rest for settle_time, then turn the mill at the scene's speed and
// direction for spinup_revolutions, calling check_stop as step_checking_stop does.
// Accounting is reset afterwards.
void settle_and_spin_up(Engine& engine, const Scene& scene, double direction_sign,
                        const std::function<void()>& check_stop = {});

// Number of steps for a given simulated time.
int steps_for(double seconds, double dt_s);

// Disks per thread of a soft step when the thread count fits the charge's size
// (SolverDef::threads_fit_size). A smaller share can pay (3k disks on two threads: 1.33-1.38x)
// but only while the cores pass cache lines quickly; on a host that moves its virtual CPUs
// apart it runs slower than one thread (0.73x), where 10k disks still break even
// (docs/benchmarks.md, "Threads").
constexpr std::size_t kDisksPerStepThread = 4096;

// The threads a soft step of `disks` disks uses: the settings' count, or with
// threads_fit_size at most one per kDisksPerStepThread disks (at least one).
int step_thread_count(const SolverDef& solver, std::size_t disks);

}  // namespace millwear
