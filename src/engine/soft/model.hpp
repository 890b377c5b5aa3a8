#pragma once
// The soft backend's model: the constants derived once from the scene, the mill and the
// sizes of the charge (MuJoCo's mj_setConst job), and the liner, replaced by set_liner
// after a wear update. Every stage of the step reads them by const reference; the step
// never changes them.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/charge.hpp"
#include "mill/mill.hpp"
#include "scene/scene.hpp"

namespace millwear::soft {

// A soft row at the substep h (contact_solver.cpp): with w = 2 pi f,
//   bias_rate = w / (2 zeta + h w), mass_scale = h w (2 zeta + h w) / (1 + h w (2 zeta + h w)),
//   impulse_scale = 1 / (1 + h w (2 zeta + h w)).
struct Softness {
  double bias_rate = 0, mass_scale = 1, impulse_scale = 0;
};
Softness make_softness(double hertz, double zeta, double h);

// Contact materials by species. Disk pairs mix as in Box2D: friction the geometric mean,
// restitution the larger; rolling resistance the larger coefficient (times the pair's
// reduced radius where the row is built).
struct Materials {
  int species = 1;
  std::vector<double> pair_friction, pair_restitution, pair_rolling;  // species x species
  std::vector<double> liner_friction, liner_restitution, rolling;     // per species
  std::size_t pair(std::uint8_t a, std::uint8_t b) const {
    return static_cast<std::size_t>(a) * static_cast<std::size_t>(species) + b;
  }
};

struct Model {
  double dt_s = 0.0;  // the scene's solver.time_step
  int substeps = 4;
  double substep_s = 0.0;  // dt_s / substeps
  Softness pair_softness, liner_softness;  // at the substep
  double push_out_m_s = 1.0;               // fastest the soft bias pushes an overlap apart:
                                           // solver.push_out x r_min, or carried_push_out_m_s
  double restitution_threshold_m_s = 0.1;  // slower impacts do not bounce
  double margin_base_m = 0.0;              // speculative margin of a disk at rest
  double r_min_m = 0.0, r_max_m = 0.0;     // smallest and largest disk radius
  double shape_band_m = 0.0;               // charge-shape band beyond the liner's own depth
  double mill_radius_m = 0.0;
  Materials materials;
};

// The push-out speed at which a contact of the lightest disk holds kCarriedWeights (8) times
// the heaviest disk's weight (model.cpp): the model's push-out is at least this, for the
// masses of the disks as filled.
double carried_push_out_m_s(const SolverDef& solver, double heaviest_kg, double lightest_kg);

Model build_model(const Scene& scene, const MillGeometry& mill, const ChargeState& initial);

// The liner as the step sees it. The angle-bin lookup is not here: it is rebuilt for more
// reach when a fast disk needs it, so it belongs to the engine's data.
struct LinerModel {
  MillGeometry mill;
  std::vector<std::uint8_t> edge_is_shell;  // per edge: its work goes to the shell
  double max_r_m = 0.0;                     // farthest liner point from the axis
  double band_m = 0.0;                      // liner depth: farthest minus nearest point
};

LinerModel build_liner_model(const MillGeometry& mill);

}  // namespace millwear::soft
