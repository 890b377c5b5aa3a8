// Filling the mill: draw disk sizes to the scene's size distribution and filling, then
// place them without overlap by random sequential addition in the lower part of the mill,
// largest first. The bed then settles under gravity in the engine.
#include <algorithm>
#include <cmath>
#include <random>

#include "common/units.hpp"
#include "common/errors.hpp"
#include "engine/engine.hpp"
#include "scene/filling.hpp"
#include "scene/limits.hpp"

namespace millwear {

namespace {


struct DiskDraw {
  double diameter_m;
  std::uint8_t species;
};

// Deterministic uniform in [0, 1): 53 random bits (independent of the library's
// distribution implementation).
double uniform01(std::mt19937_64& rng) { return (rng() >> 11) * (1.0 / 9007199254740992.0); }

std::vector<DiskDraw> draw_sizes(const Scene& scene, std::mt19937_64& rng) {
  const ChargeDef& c = scene.charge;
  std::vector<DiskDraw> disks;
  for (std::size_t k = 0; k < c.species.size(); ++k) {
    const SpeciesDef& sp = c.species[k];
    const auto sp_id = static_cast<std::uint8_t>(k);
    if (!sp.diameters_m.empty()) {
      // Whole disks per size by largest remainder (scene/filling.hpp).
      const std::vector<std::int64_t> n = disks_per_size(scene, k);
      for (std::size_t j = 0; j < sp.diameters_m.size(); ++j)
        for (std::int64_t i = 0; i < n[j]; ++i) disks.push_back({sp.diameters_m[j], sp_id});
    } else {
      const double budget = species_area_m2(scene, k);
      const double cutoff = sp.is_ball ? 0.0 : scene.solver.size_cutoff_m;
      const double lo = std::max(sp.d_min_m, std::min(cutoff, sp.d_max_m));
      const double hi = sp.d_max_m;
      double area = 0.0;
      while (area < budget) {
        const double d = lo + (hi - lo) * uniform01(rng);
        const double a = 0.25 * kPi * d * d;
        if (area + 0.5 * a > budget) break;
        disks.push_back({d, sp_id});
        area += a;
      }
    }
  }
  // Largest first: random sequential addition packs far better that way. A stable sort by
  // diameter keeps equal sizes in the order drawn, so the order is deterministic.
  std::stable_sort(disks.begin(), disks.end(), [](const DiskDraw& a, const DiskDraw& b) {
    return a.diameter_m > b.diameter_m;
  });
  return disks;
}

// Area of the part of a circle of radius r below the horizontal line y = h.
double segment_area_below(double r, double h) {
  h = std::clamp(h, -r, r);
  return r * r * std::acos(-h / r) + h * std::sqrt(r * r - h * h);
}

// The fill got stuck: random placement fills at most about 55% of a circle with disks of one
// size (less near its edge; mixed sizes, placed largest first, fill more), below the share
// check_charge_fits allows. Names the filling, and what the disks placed would take.
InputError unplaceable(const Scene& scene, double r_place, const std::vector<double>& placed_r,
                       const std::vector<DiskDraw>& draws) {
  double placed_m2 = 0.0, all_m2 = 0.0;
  for (double r : placed_r) placed_m2 += kPi * r * r;
  for (const DiskDraw& d : draws) all_m2 += 0.25 * kPi * d.diameter_m * d.diameter_m;
  const double scale = placed_m2 / all_m2;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "a filling whose disks can be placed without overlap inside the lifter tips: random placement "
                "put %zu of the %zu disks (%.0f%% of the circle of radius %.4g mm) and found no room for the next; "
                "a filling below %.3g",
                placed_r.size(), draws.size(), 100.0 * placed_m2 / (kPi * r_place * r_place), r_place * 1e3,
                down_to_3_digits(scene.charge.filling * scale));
  std::string expected = buf;
  if (scene.charge.ball_filling > 0.0) {
    std::snprintf(buf, sizeof buf, " with a ball_filling below %.3g", down_to_3_digits(scene.charge.ball_filling * scale));
    expected += buf;
  }
  return InputError(scene.source_file, "charge.filling", expected);
}

}  // namespace

ChargeState fill_charge(const Scene& scene, const MillGeometry& mill) {
  std::mt19937_64 rng(scene.solver.seed);
  const double R = mill.radius_m;
  // The disk counts, and room for them inside the lifter tips, before anything is placed
  // (every command checks all the limits on its own too, before it writes anything).
  check_filling(scene, scene.source_file);
  check_charge_fits(scene, mill, scene.source_file);
  std::vector<DiskDraw> draws = draw_sizes(scene, rng);
  ChargeState s;
  s.mill_speed_rad_s = 0.0;
  if (draws.empty()) return s;

  // Disks go inside the circle through the lifter tips, with a small clearance.
  const double d_max = draws.front().diameter_m;
  const double r_place = charge_placement_radius_m(mill, d_max);
  double solid = 0.0;
  for (const auto& d : draws) solid += 0.25 * kPi * d.diameter_m * d.diameter_m;

  // Region below y_top holding about 2.5x the solid area: loose enough for quick RSA.
  double lo = -r_place, hi = r_place;
  for (int it = 0; it < 60; ++it) {
    const double mid = 0.5 * (lo + hi);
    (segment_area_below(r_place, mid) < 2.5 * solid ? lo : hi) = mid;
  }
  double y_top = hi;

  // Uniform grid for overlap checks: cell = largest diameter, so 3x3 cells suffice.
  const double cell = d_max;
  const int n_cells = static_cast<int>(std::ceil(2.0 * r_place / cell)) + 1;
  std::vector<std::vector<int>> grid(static_cast<std::size_t>(n_cells) * n_cells);
  auto cell_of = [&](double v) {
    return std::clamp(static_cast<int>((v + r_place) / cell), 0, n_cells - 1);
  };

  const std::size_t n = draws.size();
  s.position_m.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double r = 0.5 * draws[i].diameter_m;
    bool placed = false;
    for (int attempt = 0; !placed; ++attempt) {
      if (attempt > 0 && attempt % 4000 == 0) y_top = std::min(r_place, y_top + 0.05 * R);
      if (attempt > 200000) throw unplaceable(scene, r_place, s.radius_m, draws);
      const double y = -r_place + (y_top + r_place) * uniform01(rng);
      const double x = r_place * (2.0 * uniform01(rng) - 1.0);
      const Vec2 p{x, y};
      if (length(p) + r > r_place) continue;
      const int cx = cell_of(x), cy = cell_of(y);
      bool overlap = false;
      for (int gy = std::max(cy - 1, 0); gy <= std::min(cy + 1, n_cells - 1) && !overlap; ++gy)
        for (int gx = std::max(cx - 1, 0); gx <= std::min(cx + 1, n_cells - 1) && !overlap; ++gx)
          for (int j : grid[static_cast<std::size_t>(gy) * n_cells + gx]) {
            const double rr = r + s.radius_m[static_cast<std::size_t>(j)];
            if (length_sq(p - s.position_m[static_cast<std::size_t>(j)]) < rr * rr) { overlap = true; break; }
          }
      if (overlap) continue;
      grid[static_cast<std::size_t>(cy) * n_cells + cx].push_back(static_cast<int>(i));
      s.position_m.push_back(p);
      s.radius_m.push_back(r);
      placed = true;
    }
  }
  const double thickness = scene.slice_thickness();
  s.velocity_m_s.assign(n, Vec2{});
  s.angle_rad.assign(n, 0.0);
  s.spin_rad_s.assign(n, 0.0);
  s.active.assign(n, 1);
  s.species.resize(n);
  s.mass_kg.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    s.species[i] = draws[i].species;
    const double rho = scene.charge.species[draws[i].species].density_kg_m3;
    // A disk stands for a cylinder of the slice's thickness.
    s.mass_kg[i] = rho * kPi * s.radius_m[i] * s.radius_m[i] * thickness;
  }
  return s;
}

}  // namespace millwear
