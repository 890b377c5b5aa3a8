#include "engine/soft/disks.hpp"

namespace millwear::soft {

Disks load_disks(const ChargeState& charge) {
  Disks d;
  d.n = static_cast<int>(charge.size());
  const auto n = static_cast<std::size_t>(d.n);
  d.id.resize(n);
  d.slot.resize(n);
  d.body.resize(n + 1);
  for (auto* v : {&d.x, &d.y, &d.angle, &d.radius, &d.mass}) v->resize(n);
  d.active.resize(n);
  d.species.resize(n);
  d.margin.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    d.id[i] = static_cast<int>(i);
    d.slot[i] = static_cast<int>(i);
    d.x[i] = charge.position_m[i].x;
    d.y[i] = charge.position_m[i].y;
    Body& b = d.body[i];
    b.vx = charge.velocity_m_s[i].x;
    b.vy = charge.velocity_m_s[i].y;
    b.w = charge.spin_rad_s[i];
    d.angle[i] = charge.angle_rad[i];
    d.radius[i] = charge.radius_m[i];
    d.mass[i] = charge.mass_kg[i];
    d.species[i] = charge.species[i];
    d.active[i] = charge.active[i];
    // A disk's moment of inertia is m r^2 / 2.
    b.im = d.active[i] ? 1.0 / d.mass[i] : 0.0;
    b.ii = d.active[i] ? 2.0 / (d.mass[i] * d.radius[i] * d.radius[i]) : 0.0;
    b.radius = d.radius[i];
  }
  return d;
}

StepStart make_step_start(int n) {
  StepStart s;
  s.y.assign(static_cast<std::size_t>(n), 0.0);
  s.v.assign(static_cast<std::size_t>(n), StartVelocity{});
  return s;
}

void record_step_start(Disks& disks, StepStart& start, Workers& workers) {
  workers.run_disks(disks.n, [&](int i0, int i1) {
    for (auto k = static_cast<std::size_t>(i0); k < static_cast<std::size_t>(i1); ++k) {
      Body& b = disks.body[k];
      start.y[k] = disks.y[k];
      start.v[k] = {b.vx, b.vy, b.w};
      b.dpx = 0.0;
      b.dpy = 0.0;
    }
  });
}

}  // namespace millwear::soft
