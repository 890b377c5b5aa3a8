#pragma once
// The files of `millwear charge`: charge_summary.csv (quantity, value, unit), liner_work.csv
// (shear and impact power per liner edge), spectrum.csv, contacts.csv, snapshot.csv and the
// ParaView files vtk/NAME.pvd (study/vtk_output.hpp) as the scene's outputs ask (docs/run.md
// lists their columns).
#include <string>

#include "engine/charge_run.hpp"
#include "scene/scene.hpp"

namespace millwear {

// Writes every file atomically into `out` (which exists). wall_s is the run's wall time.
void write_charge_outputs(const std::string& out, const Scene& scene, const ChargeRunResult& r, double wall_s);

}  // namespace millwear
