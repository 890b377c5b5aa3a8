#pragma once
// The files of `millwear charge`: charge_summary.csv (quantity, value, unit), liner_work.csv
// (shear and impact power per liner edge), spectrum.csv, contacts.csv, the snapshot
// (snapshot_NAME.csv, liner_NAME.csv in the run's formats) and the ParaView files
// vtk/NAME.pvd (study/vtk_output.hpp) as the scene's outputs ask, impacts.csv (first impacts
// by angle) and trajectories_NAME.csv (flight paths) (docs/run.md, docs/trajectories.md list
// their columns); then the spectrum, snapshot, impacts and trajectories figures.
#include <string>
#include <vector>

#include "metrics/charge_summary.hpp"
#include "metrics/trajectories.hpp"
#include "scene/scene.hpp"
#include "study/charge_run.hpp"

namespace millwear {

// What a charge window is set against: Morrell's C-model and Austin's SAG equation for this
// mill and charge (NaN where a model has no estimate), and the flights from the lifters.
struct ChargeEstimates {
  MorrellResult morrell;
  double austin_W_per_m = 0.0;
  ImpactSummary impacts;
};
ChargeEstimates charge_estimates(const Scene& scene, const ChargeRunResult& r);

// Writes every file atomically into `out` (which exists) and returns their paths. wall_s is
// the run's wall time.
std::vector<std::string> write_charge_outputs(const std::string& out, const Scene& scene, const ChargeRunResult& r,
                                              const ChargeEstimates& estimates, double wall_s);

// Every file name, relative to OUT, that write_charge_outputs and render_charge_figures may
// write for the scene (the tables, the figures and their data, the ParaView series' index).
std::vector<std::string> charge_output_names(const Scene& scene);

// OUT/plots/spectrum, snapshot_NAME, impacts_NAME and trajectories_NAME (PNG and SVG) from
// those files. Returns the
// figures written; throws RunError when gnuplot is missing or fails (plots/plots.hpp).
std::vector<std::string> render_charge_figures(const std::string& out, const Scene& scene);

}  // namespace millwear
