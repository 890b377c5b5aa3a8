#pragma once
// Fidelity presets: the speed-against-accuracy knobs in one place.
//
// A preset fills the numerical settings of a scene; the physics (mill, charge, wear rate)
// is never touched. A key the scene file sets itself beats the preset: apply_fidelity
// skips every field whose scene key is in Scene::explicit_keys.
//
// | field (scene key)                      | draft   | standard | reference | what it trades        |
// |----------------------------------------|---------|----------|-----------|-----------------------|
// | backend (solver.backend)               | soft    | soft     | soft      | our solver: faster    |
// |                                        |         |          |           | than the library,     |
// |                                        |         |          |           | converged friction    |
// | substeps (solver.substeps, soft only)  | 4       | 4        | 4         | contact stiffness     |
// | time_step_s (solver.time_step, s)      | 1/200   | 1/200    | 1/1000    | contact resolution;   |
// |   ... on the box2d backend             | 1/300   | 1/400    | 1/1000    | (no substeps)         |
// |                                        |         |          |           | escapes at large dt   |
// | velocity_iterations (box2d only)       | 6       | 8        | 10        | contact force accuracy|
// | position_iterations (box2d only)       | 2       | 3        | 4         | overlap removal       |
// | window_revolutions (wear.*, rev)       | 1       | 1.5      | 4         | statistics (rule 2)   |
// | target_rel_uncertainty                 | off     | 10%      | 5%        | rule 2: the window    |
// |   (wear.target_uncertainty)            |         |          |           | grows (up to 4x) until|
// |                                        |         |          |           | the wear rate's error |
// |                                        |         |          |           | meets it              |
// | max_depth_step_m (wear.max_depth_step) | 8 mm    | 6 mm     | 2 mm      | geometry feedback     |
// |                                        |         |          |           | (staged, rule 1)      |
// | factor (wear.factor)                   | 2e6     | 1e6      | 5e5       | continuous mode: sim  |
// |                                        |         |          |           | time per real time    |
// | size_cutoff_m (solver.size_cutoff)     | 0       | 0        | 0         | disk count (see note) |
// | shell_edge_m (lifters.shell_edge)      | 60 mm   | 20 mm    | 20 mm     | liner resolution:     |
// | lifter_edge_m (lifters.lifter_edge)    | 30 mm   | 10 mm    | 10 mm     | the knob that matters |
//
// Notes.
// - time step: the Box2D library on the probe mill (bench/probe_scene.hpp) lost 0 of 3,000
//   disks at 1/600 s and 7 of 3,000 at 1/240 s. The stability sweep (docs/stability.md) puts the edge
//   at dt <= 1.6 r_min / (omega R + sqrt(2 g D)) per (sub)step and the run refuses a larger
//   one (scene/limits.hpp): on the SAG scenes the 1/200 s of draft and standard moves 1.93
//   smallest radii a step (0.48 a substep). The soft backend is checked per substep; the
//   library backend has no substeps (1/200 s would be refused there: at most about 1/241 s
//   on the SAG scenes), so a scene on it gets the preset's box2d_time_step_s. A scene with much smaller particles
//   must set solver.time_step itself.
// - standard's time step and mesh: docs/fidelity.md gives each preset's and each knob's
//   distance from the reference, its noise floor and its speed-up, measured by
//   `millwear tradeoff` on the default comparison. Standard shares the reference's 20/10 mm
//   edges; draft takes standard's time step (on the library backend a longer one, 1/300 s
//   against 1/400 s) with coarser edges and a shorter window.
// - backend: the soft solver is the default of every preset (docs/soft-solver.md: faster
//   than the library at better accuracy); a scene that names solver.backend keeps it.
// - measured: `millwear tradeoff` runs every preset and one knob at a time against
//   reference; docs/fidelity.md has the table the presets were checked on.
// - factor: the paper saw 5e5 and 1e6 give the same profile and 1e7 deviate (rule 1).
//   It only matters in continuous mode; staged mode advances by the depth bound.
// - size cut-off: an absolute size (m) means something different in every scene (a 100 mm
//   cut would empty a lab mill), so every preset keeps all sizes; a scene or the tradeoff
//   ladder sets solver.size_cutoff itself.
// - mesh and depth bound are absolute lengths sized for an industrial mill (lifters
//   ~100-250 mm); a small mill sets lifters.*_edge and wear.max_depth_step itself.
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace millwear {

// A preset's knobs. A default-made FidelityDef is the `standard` preset: its fields take
// the scene defaults (SolverDef, WearDef, MillMeshDef), so every default lives in one place
// and `standard` is what a scene gets when it names nothing.
struct FidelityDef {
  std::string name = "standard";
  double time_step_s = SolverDef{}.time_step_s;
  int velocity_iterations = SolverDef{}.velocity_iterations;
  int position_iterations = SolverDef{}.position_iterations;
  double window_revolutions = WearDef{}.window_revolutions;
  double target_rel_uncertainty = WearDef{}.target_rel_uncertainty;
  double max_depth_step_m = WearDef{}.max_depth_step_m;
  double factor = WearDef{}.factor;
  double size_cutoff_m = SolverDef{}.size_cutoff_m;
  double shell_edge_m = MillMeshDef{}.shell_edge_m;
  double lifter_edge_m = MillMeshDef{}.lifter_edge_m;
  Backend backend = SolverDef{}.backend;     // solver.backend
  int substeps = SolverDef{}.substeps;       // solver.substeps (soft backend only)
  // solver.time_step when the scene runs the library backend, which has no substeps and
  // needs a smaller step than the soft backend's (scene/limits.hpp).
  double box2d_time_step_s = 1.0 / 400.0;
};

// The three presets, fastest first: draft, standard, reference.
const std::vector<FidelityDef>& fidelity_presets();
// Their names, in the same order ("draft", "standard", "reference").
std::vector<std::string> fidelity_names();
// The preset called name; throws InputError (key "fidelity") for an unknown name.
const FidelityDef& fidelity_preset(const std::string& name);
// Set the preset's fields on the scene, except those the scene file set explicitly, and
// record the preset's name in scene.fidelity. Throws InputError for an unknown name.
void apply_fidelity(Scene& scene, const std::string& name);

}  // namespace millwear
