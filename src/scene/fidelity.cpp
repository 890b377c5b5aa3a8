// Fidelity presets (the table and its reasons are in fidelity.hpp).
#include "scene/fidelity.hpp"

#include "common/errors.hpp"

namespace millwear {

const std::vector<FidelityDef>& fidelity_presets() {
  static const std::vector<FidelityDef> presets = [] {
    // standard: the scene defaults themselves (FidelityDef's own defaults).
    const FidelityDef standard;
    // draft: fewer library iterations, a shorter window, larger wear updates and a coarser
    // mesh, at the same time step (the library backend's own step longer).
    FidelityDef draft = standard;
    draft.name = "draft";
    draft.velocity_iterations = 6;
    draft.position_iterations = 2;
    draft.window_revolutions = 1.0;
    draft.target_rel_uncertainty = 0.0;
    draft.max_depth_step_m = 0.008;
    draft.factor = 2e6;
    draft.shell_edge_m = 0.060;
    draft.lifter_edge_m = 0.030;
    draft.box2d_time_step_s = 1.0 / 300.0;
    // reference: the converged settings every other preset is measured against.
    FidelityDef reference = standard;
    reference.name = "reference";
    reference.time_step_s = 1.0 / 1000.0;
    reference.velocity_iterations = 10;
    reference.position_iterations = 4;
    reference.window_revolutions = 4.0;
    reference.target_rel_uncertainty = 0.05;
    reference.max_depth_step_m = 0.002;
    reference.factor = 5e5;
    reference.box2d_time_step_s = 1.0 / 1000.0;
    return std::vector<FidelityDef>{draft, standard, reference};
  }();
  return presets;
}

std::vector<std::string> fidelity_names() {
  std::vector<std::string> names;
  for (const auto& p : fidelity_presets()) names.push_back(p.name);
  return names;
}

const FidelityDef& fidelity_preset(const std::string& name) {
  std::string all;
  for (const auto& p : fidelity_presets()) {
    if (p.name == name) return p;
    all += (all.empty() ? "" : ", ") + p.name;
  }
  throw InputError("", "fidelity", "one of " + all + "; got \"" + name + "\"");
}

void apply_fidelity(Scene& scene, const std::string& name) {
  const FidelityDef& p = fidelity_preset(name);
  if (!scene.file_sets("solver.backend")) scene.solver.backend = p.backend;
  // The file may give the time step either way; both mean it chose one.
  if (!scene.file_sets("solver.time_step") && !scene.file_sets("solver.steps_per_second"))
    scene.solver.time_step_s = scene.solver.backend == Backend::Box2D ? p.box2d_time_step_s : p.time_step_s;
  if (!scene.file_sets("solver.substeps")) scene.solver.substeps = p.substeps;
  if (!scene.file_sets("solver.velocity_iterations"))
    scene.solver.velocity_iterations = p.velocity_iterations;
  if (!scene.file_sets("solver.position_iterations"))
    scene.solver.position_iterations = p.position_iterations;
  if (!scene.file_sets("solver.size_cutoff")) scene.solver.size_cutoff_m = p.size_cutoff_m;
  if (!scene.file_sets("wear.window_revolutions"))
    scene.wear.window_revolutions = p.window_revolutions;
  if (!scene.file_sets("wear.target_uncertainty")) scene.wear.target_rel_uncertainty = p.target_rel_uncertainty;
  if (!scene.file_sets("wear.max_depth_step")) scene.wear.max_depth_step_m = p.max_depth_step_m;
  if (!scene.file_sets("wear.factor")) scene.wear.factor = p.factor;
  if (!scene.file_sets("lifters.shell_edge")) scene.mill.mesh.shell_edge_m = p.shell_edge_m;
  if (!scene.file_sets("lifters.lifter_edge")) scene.mill.mesh.lifter_edge_m = p.lifter_edge_m;
  scene.fidelity = p.name;
}

}  // namespace millwear
