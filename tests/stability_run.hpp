#pragma once
// The stability suite's runner, without GoogleTest so bench/stability_sweep.cpp can use it:
// a tiny mill built in code and a short run that watches the state (see
// tests/stability_common.hpp for the check every case makes, docs/stability.md for the
// limits found).
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/errors.hpp"
#include "engine/engine.hpp"
#include "scene/limits.hpp"
#include "scene/scene.hpp"

namespace millwear::stability {

constexpr double kPiS = 3.14159265358979323846;

// A 0.6 m mill, 12 lab-size 2x30 lifters (20 mm high), steel balls of diameters
// [d_min_mm, ratio * d_min_mm] at 20% filling, 75% of critical: about 100 disks at 15 mm.
inline Scene tiny_mill(double d_min_mm = 15.0, double size_ratio = 1.67, double filling = 0.20) {
  Scene s;
  s.name = "tiny";
  s.source_file = "(stability test)";
  s.mill.diameter_m = 0.6;
  s.mill.length_m = 0.3;
  s.mill.speed_fraction_critical = 0.75;
  s.mill.rows = 12;
  TrapezoidDef t;
  t.height_m = 0.020;
  t.top_width_m = 0.010;
  t.leading_face_angle_rad = t.trailing_face_angle_rad = 30.0 * kPiS / 180.0;
  s.mill.lifter.points = trapezoid_points(t);
  s.mill.lifter.name = "tiny-2x30";
  s.mill.mesh.shell_edge_m = 0.010;
  s.mill.mesh.lifter_edge_m = 0.002;
  SpeciesDef sp;
  sp.name = "ball";
  sp.is_ball = true;
  sp.density_kg_m3 = 7800.0;
  sp.d_min_m = d_min_mm * 1e-3;
  sp.d_max_m = size_ratio * d_min_mm * 1e-3;
  sp.friction = sp.friction_liner = 0.3;
  sp.restitution = sp.restitution_liner = 0.3;
  sp.rolling_resistance = 0.05;
  s.charge.species = {sp};
  s.charge.filling = filling;
  s.charge.ball_filling = filling;
  s.solver.backend = Backend::Box2D;
  s.solver.time_step_s = 1.0 / 1000.0;
  s.solver.settle_time_s = 0.3;
  s.solver.spinup_revolutions = 0.25;
  s.wear.smoothing_radius_m = 0.002;
  s.wear.window_revolutions = 2.0;
  s.wear.max_depth_step_m = 0.0005;
  s.wear.replacement_height_m = 0.005;
  return s;
}

struct Outcome {
  bool completed = false;
  std::string error;           // the message when the run stopped (InputError / RunError)
  std::size_t disks = 0;
  long long escaped = 0, non_finite = 0;
  bool finite = true;          // every active disk finite at every check
  double max_speed_m_s = 0.0;  // largest disk speed seen
  double speed_bound_m_s = 0.0;
  std::vector<std::string> events;
};

// The speed no disk of a sound run exceeds: twice the fastest a disk can fall and be
// carried (shell speed plus a free fall across the mill, impact_speed_m_s), plus 1 m/s for
// the settling of a freshly placed bed. Energy grows as the square: a run inside this
// bound has kinetic energy under about 4x the largest physical value.
inline double speed_bound(const Scene& s) { return 2.0 * impact_speed_m_s(s) + 1.0; }

// Fill, settle, spin up, then turn `revolutions` (or 1 s at rest), checking the state every
// 10 steps. Errors the guards throw are caught and returned; anything else propagates.
// guarded = false skips the limit checks of settle_and_spin_up (the sweep uses it to see
// what happens beyond a limit); the settle and spin-up are otherwise the same.
inline Outcome run_briefly(const Scene& scene, double revolutions = 1.0, bool guarded = true) {
  Outcome o;
  o.speed_bound_m_s = speed_bound(scene);
  try {
    // As every command does: the limits before anything is filled.
    if (guarded) check_run_limits(scene, scene.source_file);
    const MillGeometry mill = build_scene_mill(scene);
    auto engine = make_engine(scene, mill, fill_charge(scene, mill), accounting_options_for(scene));
    o.disks = engine->state().size();
    if (guarded) {
      settle_and_spin_up(*engine, scene, 1.0);
    } else {
      const double dt = engine->time_step_s();
      engine->set_mill_speed(0.0);
      engine->step(steps_for(scene.solver.settle_time_s, dt));
      engine->set_mill_speed(scene.angular_speed_rad_s());
      if (scene.angular_speed_rad_s() > 0.0)
        engine->step(steps_for(scene.solver.spinup_revolutions * scene.revolution_time_s(), dt));
      engine->reset_window();
    }
    const double seconds = scene.mill.speed_fraction_critical > 0.0 ? revolutions * scene.revolution_time_s() : 1.0;
    const int steps = steps_for(seconds, engine->time_step_s());
    for (int done = 0; done < steps; done += 10) {
      engine->step(std::min(10, steps - done));
      engine->reset_window();
      const ChargeState& st = engine->state();
      for (std::size_t i = 0; i < st.size(); ++i) {
        if (!st.active[i]) continue;
        const double v = length(st.velocity_m_s[i]);
        if (!std::isfinite(v) || !std::isfinite(st.position_m[i].x) || !std::isfinite(st.position_m[i].y))
          o.finite = false;
        else
          o.max_speed_m_s = std::max(o.max_speed_m_s, v);
      }
    }
    // Escapes while settling and spinning up count too: every one is an event.
    for (const auto& e : engine->events()) {
      o.events.push_back(e.what);
      if (e.what.find("non-finite") != std::string::npos) ++o.non_finite;
      else if (e.what.find("escaped") != std::string::npos || e.what.find("leaked") != std::string::npos) ++o.escaped;
    }
    o.completed = true;
  } catch (const InputError& e) {
    o.error = e.what();
  } catch (const RunError& e) {
    o.error = e.what();
  }
  return o;
}

inline std::string describe(const Outcome& o) {
  std::string s = o.completed ? "completed" : "stopped: " + o.error;
  s += "; disks " + std::to_string(o.disks) + ", escaped " + std::to_string(o.escaped) + ", non-finite " +
       std::to_string(o.non_finite) + ", max speed " + std::to_string(o.max_speed_m_s) + " m/s (bound " +
       std::to_string(o.speed_bound_m_s) + ")";
  if (!o.events.empty()) s += "; first event: " + o.events.front();
  return s;
}

}  // namespace millwear::stability
