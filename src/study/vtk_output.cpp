// ParaView files of a measuring window (see vtk_output.hpp).
#include "study/vtk_output.hpp"

#include <cmath>
#include <cstdio>

#include "common/units.hpp"
#include "io/atomic_write.hpp"
#include "io/run_folder.hpp"
#include "io/vtk_files.hpp"
#include "wear/archard.hpp"

namespace millwear {

LinerFields liner_fields(const Scene& scene, const MillGeometry& mill, const Accounting& w, double c_m3_per_J) {
  LinerFields f;
  const std::size_t n = mill.boundary.size();
  const double t = scene.slice_thickness();
  f.shear_W_per_m2.assign(n, 0.0);
  f.impact_W_per_m2.assign(n, 0.0);
  f.wear_rate_m_per_s.assign(n, 0.0);
  if (!(w.time_s > 0.0)) return f;
  for (std::size_t e = 0; e < n && e < w.shear_work_J.size(); ++e) {
    const double area = mill.edge_length_m[e] * t;
    f.shear_W_per_m2[e] = w.shear_work_J[e] / w.time_s / area;
    f.impact_W_per_m2[e] = w.impact_energy_J[e] / w.time_s / area;
    f.wear_rate_m_per_s[e] = boundary_edge_wear_rate_m_per_s(scene, mill, e, w.shear_work_J[e] / w.time_s, t, c_m3_per_J);
  }
  return f;
}

namespace {

io::VtkGrid particles_grid(const ChargeState& s) {
  io::VtkGrid g;
  io::VtkArray id{"id", 1, true, {}}, radius{"radius_m", 1, false, {}}, species{"species", 1, true, {}},
      velocity{"velocity_m_per_s", 3, false, {}}, speed{"speed_m_per_s", 1, false, {}},
      spin{"spin_rad_per_s", 1, false, {}};
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (!s.active[i]) continue;
    const Vec2 p = s.position_m[i], v = s.velocity_m_s[i];
    g.xyz.insert(g.xyz.end(), {p.x, p.y, 0.0});
    id.values.push_back(static_cast<double>(i));
    radius.values.push_back(s.radius_m[i]);
    species.values.push_back(s.species[i]);
    velocity.values.insert(velocity.values.end(), {v.x, v.y, 0.0});
    speed.values.push_back(std::hypot(v.x, v.y));
    spin.values.push_back(s.spin_rad_s[i]);
  }
  g.point_data = {id, radius, species, velocity, speed, spin};
  return g;
}

io::VtkGrid liner_grid(const MillGeometry& mill, double mill_angle_rad, const LinerFields& f) {
  io::VtkGrid g;
  g.cells = io::VtkCells::Lines;
  const std::size_t n = mill.boundary.size();
  io::VtkArray shear{"shear_power_W_per_m2", 1, false, f.shear_W_per_m2},
      impact{"impact_power_W_per_m2", 1, false, f.impact_W_per_m2}, wear{"wear_rate_mm_per_1000h", 1, false, {}},
      lifter{"lifter", 1, true, {}};
  for (std::size_t e = 0; e < n; ++e) {
    const Vec2 p = rotated(mill.boundary[e], mill_angle_rad);
    g.xyz.insert(g.xyz.end(), {p.x, p.y, 0.0});
    g.line_points.push_back(static_cast<std::int64_t>(e));
    g.line_points.push_back(static_cast<std::int64_t>((e + 1) % n));
    wear.values.push_back(e < f.wear_rate_m_per_s.size() ? mm_per_1000h(f.wear_rate_m_per_s[e]) : 0.0);
    lifter.values.push_back(mill.edges[e].owner == EdgeOwner::Lifter ? 1.0 : 0.0);
  }
  shear.values.resize(n, 0.0);
  impact.values.resize(n, 0.0);
  g.cell_data = {shear, impact, wear, lifter};
  return g;
}

}  // namespace

std::vector<std::string> write_vtk_series(const std::string& dir, const std::string& base, const Scene&,
                                          const MillGeometry& mill, const std::vector<ChargeState>& frames,
                                          const LinerFields& liner) {
  std::vector<std::string> files;
  if (frames.empty()) return files;
  io::ensure_dir(dir);
  std::vector<io::PvdEntry> entries;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    char num[24];
    std::snprintf(num, sizeof num, "%04zu", k);
    const std::string pname = base + "_particles_" + num + ".vtu", lname = base + "_liner_" + num + ".vtu";
    io::write_file_atomic(io::join_path(dir, pname), io::vtu_text(particles_grid(frames[k])));
    io::write_file_atomic(io::join_path(dir, lname), io::vtu_text(liner_grid(mill, frames[k].mill_angle_rad, liner)));
    files.push_back(io::join_path(dir, pname));
    files.push_back(io::join_path(dir, lname));
    entries.push_back({frames[k].time_s, 0, pname});
    entries.push_back({frames[k].time_s, 1, lname});
  }
  const std::string pvd = io::join_path(dir, base + ".pvd");
  io::write_file_atomic(pvd, io::pvd_text(entries));
  files.push_back(pvd);
  return files;
}

}  // namespace millwear
