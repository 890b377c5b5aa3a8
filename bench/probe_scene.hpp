#pragma once
// The probe scene, shared by the engine benchmarks: a
// 5 m mill, 24 trapezoid lifters (150 mm high, 100 mm top, 30 deg faces), 75% of critical,
// disks of radius r_min to 1.67 r_min at 30% filling, dt 1/600 s.
#include "profiles/profile.hpp"
#include "scene/scene.hpp"

namespace millwear::bench {

inline Scene probe_scene(double r_min_m) {
  Scene s;
  s.name = "probe";
  s.source_file = "(bench)";
  s.mill.diameter_m = 5.0;
  s.mill.length_m = 1.0;
  s.mill.speed_fraction_critical = 0.75;
  s.mill.rows = 24;
  TrapezoidDef t;
  t.height_m = 0.15;
  t.top_width_m = 0.10;
  t.leading_face_angle_rad = t.trailing_face_angle_rad = 30.0 * 3.14159265358979 / 180.0;
  s.mill.lifter.points = trapezoid_points(t);
  s.mill.lifter.name = "probe";
  s.mill.mesh.shell_edge_m = 0.05;
  s.mill.mesh.lifter_edge_m = 0.02;
  SpeciesDef sp;
  sp.name = "ball";
  sp.is_ball = true;
  sp.density_kg_m3 = 2700.0;
  sp.d_min_m = 2.0 * r_min_m;
  sp.d_max_m = 2.0 * 1.67 * r_min_m;
  sp.friction = sp.friction_liner = 0.5;
  sp.restitution = sp.restitution_liner = 0.4;
  s.charge.species = {sp};
  s.charge.filling = 0.30;
  s.charge.ball_filling = 0.30;
  s.charge.bulk_packing = 0.8;
  s.solver.backend = Backend::Box2D;  // the benchmarks name the backend they run
  s.solver.time_step_s = 1.0 / 600.0;
  s.solver.settle_time_s = 1.0;
  s.solver.spinup_revolutions = 0.25;
  return s;
}

}  // namespace millwear::bench
