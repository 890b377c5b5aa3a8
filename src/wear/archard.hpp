#pragma once
// Archard's law per liner edge: A dh = C dw, with A the edge's area (length x slice
// thickness) and dw the shear work the charge did on it. The shear work arrives per mill
// boundary edge; wear acts on liner units (one per row, or one shared by every row), so the
// work is first gathered into unit edges.
#include <vector>

#include "mill/mill.hpp"
#include "scene/scene.hpp"

namespace millwear {

// Depth (m) that shear_work_J removes from an edge of edge_length_m in a slice of
// thickness_m at wear rate C (m^3/J).
inline double archard_depth_m(double shear_work_J, double edge_length_m, double thickness_m,
                              double wear_rate_m3_per_J) {
  return wear_rate_m3_per_J * shear_work_J / (edge_length_m * thickness_m);
}

// Edge j of a unit belongs to the lifter (its midpoint over the new lifter's base).
bool is_lifter_edge(const LinerUnit& unit, int j);

// Work (or power) per edge of the liner unit(s) in lifter-local order, from the values per
// mill boundary edge: averaged over the rows of each kind of lifter (one unit per kind) or
// one vector per row when the scene wears rows on their own.
std::vector<std::vector<double>> unit_edge_work(const MillGeometry& mill,
                                                const std::vector<double>& edge_work,
                                                bool average_rows);

// Edge lengths of a unit in the mill frame (true lengths; rows are identical copies).
std::vector<double> unit_edge_lengths(const LinerUnit& unit, double radius_m);

// Archard's depth per unit edge, read at the mesh's resolution: an edge shorter than
// min_length_m (a cut's sliver, a step of a rounded corner) takes the depth of the run of
// edges around it that is min_length_m long, as one contact's work divided by a sliver's
// length would be all noise. Longer edges keep their own. Shell edges are zero unless the
// shell wears.
// Shell edges wear at shell_rate_m3_per_J (negative: at rate_m3_per_J).
std::vector<double> edge_depths(const LinerUnit& unit, const std::vector<double>& work_J,
                                const std::vector<double>& length_m, double min_length_m,
                                double thickness_m, double rate_m3_per_J, bool shell_wear,
                                double shell_rate_m3_per_J = -1.0);

// The real wear rate of the shell plates: wear.shell_wear_rate, else the lifters' c_real.
double shell_wear_rate(const Scene& scene, double c_real_m3_per_J);

// Archard's wear rate (m/s) of mill boundary edge e under power_W of shear in a slice of
// thickness_m (scene.slice_thickness()): a lifter edge at c_real, a shell edge at
// shell_wear_rate, or 0 when the shell does not wear.
double boundary_edge_wear_rate_m_per_s(const Scene& scene, const MillGeometry& mill, std::size_t e,
                                       double power_W, double thickness_m, double c_real_m3_per_J);

// edge_depths for every unit of the mill at the scene's mesh resolution, at the real rate
// c_real (lifters; the shell at shell_wear_rate) times `factor` (continuous mode's
// C_model = factor * C); with work in J the depths are m, with power in W m per second.
std::vector<std::vector<double>> archard_depths(const Scene& scene, const MillGeometry& mill,
                                                const std::vector<std::vector<double>>& unit_work,
                                                double c_real_m3_per_J, double factor = 1.0);

// The largest depth of any unit edge.
double deepest(const std::vector<std::vector<double>>& depths);

// Shear power on the lifter edges of a unit set, per row (W).
double lifter_power_W(const MillGeometry& mill, const std::vector<std::vector<double>>& unit_power_W);
// The same for each kind of lifter of a pattern: per row of that kind (W), one entry per kind.
std::vector<double> kind_lifter_power_W(const MillGeometry& mill, const std::vector<std::vector<double>>& unit_power_W);
// The same on the lifters' tops only: the lifter edges that reach the lifter's highest point
// (the two beside a peak, or a flat top's). Their wear sets the height a wear update takes.
double lifter_top_power_W(const MillGeometry& mill, const std::vector<std::vector<double>>& unit_power_W);
std::vector<double> kind_lifter_top_power_W(const MillGeometry& mill,
                                            const std::vector<std::vector<double>>& unit_power_W);

// The real wear rate C (m^3/J) the scene asks for: given, or calibrated from a measured
// area or height loss rate against the new liner's shear-work field (power per mill edge,
// W). Throws RunError when the lifter takes no shear work to calibrate against.
double real_wear_rate(const Scene& scene, const MillGeometry& mill,
                      const std::vector<double>& shear_power_W);

}  // namespace millwear
