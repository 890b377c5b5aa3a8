#pragma once
// A run's figures with their errors: each design's stages from its one history (batch-means
// errors) or from its replicates, and the comparison of every design with the reference.
#include <map>
#include <string>
#include <vector>

#include "metrics/estimates.hpp"
#include "scene/scene.hpp"
#include "wear/history.hpp"

namespace millwear::study {

// One history's figures with batch-means errors (lower bounds). The area's error at stage k
// adds up the errors of the wear rates of stages 0..k-1 (each rate's batch-means error over
// the hours it acts), taken as independent; the height's and the life's follow the area's
// relative error.
// A pattern of kinds adds each kind's lifter and life (kind_life_h from compute_life) in the
// same way, from each kind's own rates.
DesignEstimate estimate_history(const std::string& name, const Scene& scene, const std::map<int, StageRecord>& stages,
                                double life_h, bool life_extrapolated, const std::vector<double>& kind_life_h = {},
                                const std::vector<bool>& kind_life_extrapolated = {});

// Every design against the reference: life; area loss at the last stage both finished; power,
// specific power, collision power, utilization, liner shear power and liner wear per energy
// at the new stage.
std::vector<Verdict> compare_designs(const std::vector<DesignEstimate>& designs, const std::string& reference);

}  // namespace millwear::study
