// Numerical limits of a scene (the reasons and the measured numbers are in limits.hpp and
// docs/stability.md).
#include "scene/limits.hpp"

#include <cmath>
#include <cstdio>

#include "common/errors.hpp"

namespace millwear {

double impact_speed_m_s(const Scene& scene) {
  return scene.angular_speed_rad_s() * scene.radius_m() + std::sqrt(2.0 * kGravity * scene.mill.diameter_m);
}

double step_travel_radii(const Scene& scene) {
  const double r = scene.smallest_particle_radius_m();
  return r > 0.0 ? scene.solver.time_step_s * impact_speed_m_s(scene) / r : 0.0;
}

void check_numerical_limits(const Scene& scene, const std::string& file) {
  // The soft backend substeps; its own limit is per substep.
  const int substeps = scene.solver.backend == Backend::Soft ? std::max(1, scene.solver.substeps) : 1;
  const double travel = step_travel_radii(scene) / substeps;
  if (travel > kMaxStepTravelRadii) {
    const double r = scene.smallest_particle_radius_m();
    const double dt_max = kMaxStepTravelRadii * r * substeps / impact_speed_m_s(scene);
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "a time step of at most %.3g s (1/%.0f s): at the impact speed %.2f m/s (shell speed + "
                  "free fall across the mill) a disk would move %.2f smallest radii (%.1f mm) per %s, over the "
                  "limit of %.1f radii where disks start to leak through the liner; got %.3g s (1/%.0f s)",
                  dt_max, std::ceil(1.0 / dt_max), impact_speed_m_s(scene), travel, r * 1e3,
                  substeps > 1 ? "substep" : "step", kMaxStepTravelRadii, scene.solver.time_step_s,
                  1.0 / scene.solver.time_step_s);
    throw InputError(file, "solver.time_step", buf);
  }
}

}  // namespace millwear
