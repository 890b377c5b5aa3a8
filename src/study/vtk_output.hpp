#pragma once
// ParaView files of a measuring window (scene [outputs] vtk = true, or --vtk): the charge at
// each frame and the liner, in the world frame, as VTK XML files (io/vtk_files.hpp) with a
// .pvd index that ParaView opens as a time series:
//
//   DIR/BASE.pvd                  part 0: the particles, part 1: the liner, per frame time (s)
//   DIR/BASE_particles_NNNN.vtu   a vertex per active disk; point arrays: id, radius_m,
//                                 species (index of [[charge.species]]), velocity_m_per_s (3),
//                                 speed_m_per_s, spin_rad_per_s
//   DIR/BASE_liner_NNNN.vtu       a line per mill boundary edge, turned to the frame's mill
//                                 angle; cell arrays: shear_power_W_per_m2, impact_power_W_per_m2
//                                 (over the window), wear_rate_mm_per_1000h, lifter (1) or shell (0)
#include <string>
#include <vector>

#include "engine/accounting.hpp"
#include "engine/charge.hpp"
#include "mill/mill.hpp"
#include "scene/scene.hpp"

namespace millwear {

// The liner's fields per mill boundary edge.
struct LinerFields {
  std::vector<double> shear_W_per_m2, impact_W_per_m2, wear_rate_m_per_s;
};

// Shear and impact power per edge area from a window's sums, and Archard's wear rate at the
// real wear rate c_m3_per_J (boundary_edge_wear_rate_m_per_s: the shell at its own rate,
// 0 unless it wears).
LinerFields liner_fields(const Scene& scene, const MillGeometry& mill, const Accounting& window, double c_m3_per_J);

// Writes the files above atomically into DIR (created if needed); returns their paths, the
// .pvd last. Nothing is written for no frames.
std::vector<std::string> write_vtk_series(const std::string& dir, const std::string& base, const Scene& scene,
                                          const MillGeometry& mill, const std::vector<ChargeState>& frames,
                                          const LinerFields& liner);

}  // namespace millwear
