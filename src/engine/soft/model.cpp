#include "engine/soft/model.hpp"

#include <algorithm>
#include <cmath>

#include "common/units.hpp"
#include "geometry/vec2.hpp"

namespace millwear::soft {

namespace {

// A disk at rest keeps a margin of a tenth of the smallest radius, so that touching disks
// hold their contact from step to step (warm starting) without creeping into overlap.
constexpr double kMarginBaseRadii = 0.1;
// Restitution only for impacts faster than 1.67 mean diameters per second: the Box2D
// backend's threshold (1 unit/s at its scaling), so both backends bounce alike.
constexpr double kRestitutionThresholdSeconds = 0.6;
// The charge-shape band reaches two of the largest radii past the liner's depth.
constexpr double kShapeBandRadii = 2.0;
// With no disk, lengths are scaled from a disk of a hundredth of the mill radius.
constexpr double kEmptyChargeRadius = 0.01;
// The push-out speed is raised so that a contact of the lightest disk can hold this many
// times the heaviest disk's weight at rest (build_model). 2.5 mm rocks among 15-25 mm steel
// balls (a ball up to 290 times a rock's mass; docs/stability.md) still leaked through the
// liner at 2.8 and held at 3.6 (the lab mill at 1/1200 and 1/1250 s, three seeds each);
// 8 is over twice the clean edge.
constexpr double kCarriedWeights = 8.0;
// Above any coordinate in metres: the first value replaces it.
constexpr double kUnbounded = 1e300;

}  // namespace

Softness make_softness(double hertz, double zeta, double h) {
  const double w = 2.0 * kPi * hertz;
  const double a1 = 2.0 * zeta + h * w;
  const double a2 = h * w * a1;
  const double a3 = 1.0 / (1.0 + a2);
  return {w / a1, a2 * a3, a3};
}

// A soft row of effective mass m_e holds a steady load F with the bias F / (m_e w (2 zeta +
// h w)) (contact_solver.hpp). The bias is capped at the push-out speed, so a light disk
// pressed by a far heavier one (the rows between them have about the light disk's mass)
// sinks on through the liner once that load needs more than the cap: the cap is raised to
// what kCarriedWeights of the heaviest disk's weight on the lightest needs. The shipped
// scenes need 1-40% of their default (mass ratios 2.8 to 81), so only far larger ratios
// change anything.
double carried_push_out_m_s(const SolverDef& solver, double heaviest_kg, double lightest_kg) {
  const double h = solver.time_step_s / solver.substeps;
  const double w = 2.0 * kPi * solver.contact_hertz_used();
  const double m_e = lightest_kg * heaviest_kg / (lightest_kg + heaviest_kg);
  return kCarriedWeights * heaviest_kg * kGravity / (m_e * w * (2.0 * solver.damping_ratio + h * w));
}

Model build_model(const Scene& scene, const MillGeometry& mill, const ChargeState& initial) {
  Model m;
  m.dt_s = scene.solver.time_step_s;
  m.substeps = scene.solver.substeps;
  const double h = m.dt_s / m.substeps;
  m.substep_s = h;
  const double hertz = scene.solver.contact_hertz_used();
  // Liner contacts get twice the frequency, as static contacts do in Box2D (at most a
  // quarter of the substep rate).
  m.pair_softness = make_softness(hertz, scene.solver.damping_ratio, h);
  m.liner_softness = make_softness(2.0 * hertz, scene.solver.damping_ratio, h);
  m.mill_radius_m = mill.radius_m;

  const auto n = static_cast<int>(initial.size());
  double r_min = 0.0, r_max = 0.0, mean_d = 0.0, m_min = kUnbounded, m_max = 0.0;
  for (int i = 0; i < n; ++i) {
    const double r = initial.radius_m[static_cast<std::size_t>(i)];
    r_min = i == 0 ? r : std::min(r_min, r);
    r_max = std::max(r_max, r);
    mean_d += 2.0 * r / n;
    const double mass = initial.mass_kg[static_cast<std::size_t>(i)];
    if (mass > 0.0) m_min = std::min(m_min, mass), m_max = std::max(m_max, mass);
  }
  if (n == 0) r_min = r_max = kEmptyChargeRadius * m.mill_radius_m, mean_d = 2.0 * r_min;
  m.r_min_m = r_min;
  m.r_max_m = r_max;
  m.push_out_m_s = scene.solver.push_out_radii_per_s * r_min;
  if (m_max > 0.0) m.push_out_m_s = std::max(m.push_out_m_s, carried_push_out_m_s(scene.solver, m_max, m_min));
  m.restitution_threshold_m_s = mean_d / kRestitutionThresholdSeconds;
  m.margin_base_m = kMarginBaseRadii * r_min;
  m.shape_band_m = kShapeBandRadii * r_max;

  const auto& species = scene.charge.species;
  Materials& mat = m.materials;
  mat.species = static_cast<int>(std::max<std::size_t>(species.size(), 1));
  const auto count = static_cast<std::size_t>(mat.species);
  mat.pair_friction.assign(count * count, 0.5);
  mat.pair_restitution.assign(count * count, 0.0);
  mat.pair_rolling.assign(count * count, 0.0);
  mat.liner_friction.assign(count, 0.5);
  mat.liner_restitution.assign(count, 0.0);
  mat.rolling.assign(count, 0.0);
  for (std::size_t a = 0; a < species.size(); ++a) {
    mat.liner_friction[a] = species[a].friction_liner;
    mat.liner_restitution[a] = species[a].restitution_liner;
    mat.rolling[a] = species[a].rolling_resistance;
    for (std::size_t b = 0; b < species.size(); ++b) {
      const std::size_t k = a * species.size() + b;
      mat.pair_friction[k] = std::sqrt(species[a].friction * species[b].friction);
      mat.pair_restitution[k] = std::max(species[a].restitution, species[b].restitution);
      mat.pair_rolling[k] = std::max(species[a].rolling_resistance, species[b].rolling_resistance);
    }
  }
  return m;
}

LinerModel build_liner_model(const MillGeometry& mill) {
  LinerModel liner;
  liner.mill = mill;
  double min_r = kUnbounded;
  for (const Vec2& p : mill.boundary) {
    liner.max_r_m = std::max(liner.max_r_m, length(p));
    min_r = std::min(min_r, length(p));
  }
  liner.band_m = liner.max_r_m - min_r;
  const std::size_t n = mill.boundary.size();
  liner.edge_is_shell.resize(n);
  for (std::size_t e = 0; e < n; ++e)
    liner.edge_is_shell[e] = mill.edges[e].owner == EdgeOwner::Shell ? 1 : 0;
  return liner;
}

}  // namespace millwear::soft
