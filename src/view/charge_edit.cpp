// Adding, removing and moving disks of a running charge (see charge_edit.hpp).
#include "view/charge_edit.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "common/errors.hpp"
#include "common/units.hpp"
#include "engine/engine.hpp"
#include "geometry/polyline.hpp"

namespace millwear::view {

namespace {

// One disk, all its fields, for rebuilding the structure of arrays.
struct Disk {
  Vec2 position, velocity;
  double angle = 0.0, spin = 0.0, radius = 0.0, mass = 0.0;
  std::uint8_t species = 0;
};

std::vector<Disk> active_disks(const ChargeState& s) {
  std::vector<Disk> d;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.active[i])
      d.push_back({s.position_m[i], s.velocity_m_s[i], s.angle_rad[i], s.spin_rad_s[i], s.radius_m[i], s.mass_kg[i],
                   s.species[i]});
  return d;
}

ChargeState with_disks(const ChargeState& like, const std::vector<Disk>& disks) {
  ChargeState s;
  s.mill_angle_rad = like.mill_angle_rad;
  s.mill_speed_rad_s = like.mill_speed_rad_s;
  s.time_s = like.time_s;
  for (const Disk& d : disks) {
    s.position_m.push_back(d.position);
    s.velocity_m_s.push_back(d.velocity);
    s.angle_rad.push_back(d.angle);
    s.spin_rad_s.push_back(d.spin);
    s.radius_m.push_back(d.radius);
    s.mass_kg.push_back(d.mass);
    s.species.push_back(d.species);
    s.active.push_back(1);
  }
  return s;
}

double tip_radius(const MillGeometry& mill) {
  double r = mill.radius_m;
  for (const Vec2& p : mill.boundary) r = std::min(r, length(p));
  return r;
}

// Random sequential addition of `add` among `placed`, inside the circle through the lifter
// tips (less a clearance of a tenth of the largest diameter), on a uniform grid of cells one
// largest diameter wide. Deterministic for a given charge and seed.
void place_disks(std::vector<Disk>& placed, std::vector<Disk> add, double r_tips, std::uint64_t seed) {
  if (add.empty()) return;
  double d_max = 0.0;
  for (const Disk& d : placed) d_max = std::max(d_max, 2.0 * d.radius);
  for (const Disk& d : add) d_max = std::max(d_max, 2.0 * d.radius);
  const double r_place = r_tips - 0.1 * d_max;
  const double cell = d_max;
  const int n = static_cast<int>(std::ceil(2.0 * r_tips / cell)) + 1;
  std::vector<std::vector<int>> grid(static_cast<std::size_t>(n) * n);
  auto cell_of = [&](double v) { return std::clamp(static_cast<int>((v + r_tips) / cell), 0, n - 1); };
  auto insert = [&](int id) {
    grid[static_cast<std::size_t>(cell_of(placed[id].position.y)) * n + cell_of(placed[id].position.x)].push_back(id);
  };
  for (int i = 0; i < static_cast<int>(placed.size()); ++i) insert(i);
  std::sort(add.begin(), add.end(), [](const Disk& a, const Disk& b) { return a.radius > b.radius; });
  std::mt19937_64 rng(seed);
  auto uniform01 = [&rng] { return (rng() >> 11) * (1.0 / 9007199254740992.0); };
  for (Disk d : add) {
    bool ok = false;
    for (int attempt = 0; attempt < 20000 && !ok; ++attempt) {
      const Vec2 p{r_place * (2.0 * uniform01() - 1.0), r_place * (2.0 * uniform01() - 1.0)};
      if (length(p) + d.radius > r_place) continue;
      ok = true;
      const int cx = cell_of(p.x), cy = cell_of(p.y);
      for (int y = std::max(0, cy - 1); y <= std::min(n - 1, cy + 1) && ok; ++y)
        for (int x = std::max(0, cx - 1); x <= std::min(n - 1, cx + 1) && ok; ++x)
          for (int j : grid[static_cast<std::size_t>(y) * n + x])
            if (length(placed[j].position - p) < placed[j].radius + d.radius) {
              ok = false;
              break;
            }
      if (ok) d.position = p;
    }
    if (!ok) throw RunError("the added disks do not fit in the free space of the mill; choose a lower filling");
    d.velocity = Vec2{0.0, 0.0};
    d.spin = 0.0;
    placed.push_back(d);
    insert(static_cast<int>(placed.size()) - 1);
  }
}

std::uint64_t placement_seed(const Scene& scene, const ChargeState& now) {
  // Mixed with the disk count and the clock so each change places afresh, reproducibly.
  return scene.solver.seed * 0x9E3779B97F4A7C15ull + now.size() * 1315423911ull +
         static_cast<std::uint64_t>(std::llround(now.time_s * 1e6));
}

}  // namespace

ChargeState refill_charge(const Scene& scene, const MillGeometry& mill, const ChargeState& now) {
  const ChargeState target = fill_charge(scene, mill);  // the sizes the new filling asks for
  const std::vector<Disk> current = active_disks(now);
  std::vector<Disk> kept, add;
  const std::size_t species = std::max<std::size_t>(scene.charge.species.size(), 1);
  for (std::size_t k = 0; k < species; ++k) {
    std::vector<std::size_t> have, want;
    for (std::size_t i = 0; i < current.size(); ++i)
      if (current[i].species == k) have.push_back(i);
    for (std::size_t i = 0; i < target.size(); ++i)
      if (target.species[i] == k) want.push_back(i);
    if (want.size() <= have.size()) {
      // Drop have - want disks spread evenly through the species (no size or place favoured).
      const std::size_t drop = have.size() - want.size();
      std::vector<std::uint8_t> gone(have.size(), 0);
      for (std::size_t j = 0; j < drop; ++j) gone[(2 * j + 1) * have.size() / (2 * drop)] = 1;
      for (std::size_t j = 0; j < have.size(); ++j)
        if (!gone[j]) kept.push_back(current[have[j]]);
    } else {
      for (std::size_t i : have) kept.push_back(current[i]);
      // Add want - have disks of the new filling's sizes, spread evenly through its list.
      const std::size_t extra = want.size() - have.size();
      for (std::size_t j = 0; j < extra; ++j) {
        const std::size_t t = want[(2 * j + 1) * want.size() / (2 * extra)];
        Disk d;
        d.radius = target.radius_m[t];
        d.mass = target.mass_kg[t];
        d.species = target.species[t];
        add.push_back(d);
      }
    }
  }
  place_disks(kept, std::move(add), tip_radius(mill), placement_seed(scene, now));
  return with_disks(now, kept);
}

ChargeState fit_charge_to_liner(const Scene& scene, const MillGeometry& mill, const ChargeState& now) {
  const double r_tips = tip_radius(mill);
  Polyline ring = mill.boundary;
  ring.push_back(ring.front());
  std::vector<Disk> kept, moved;
  for (const Disk& d : active_disks(now)) {
    // Only a disk reaching past the lifter tips can touch the liner.
    bool clear = length(d.position) + d.radius < r_tips;
    if (!clear) {
      const Vec2 m = rotated(d.position, -now.mill_angle_rad);  // world -> mill frame
      clear = contains(mill.boundary, m) && distance_to_polyline(m, ring) > d.radius;
    }
    (clear ? kept : moved).push_back(d);
  }
  place_disks(kept, std::move(moved), r_tips, placement_seed(scene, now));
  return with_disks(now, kept);
}

}  // namespace millwear::view
