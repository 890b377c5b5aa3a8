// The files of `millwear charge` (see charge_outputs.hpp).
#include "study/charge_outputs.hpp"

#include <cstdio>
#include <sstream>

#include "io/atomic_write.hpp"
#include "io/run_folder.hpp"
#include "io/stage_files.hpp"
#include "plots/plots.hpp"

namespace millwear {

namespace {

std::string fmt(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

}  // namespace

// Files of a charge run: summary, shear work along the liner, spectrum, snapshot.

void write_charge_outputs(const std::string& out, const Scene& scene, const ChargeRunResult& r,
                          double wall_s) {
  const ChargeFigures& f = r.figures;
  const ChargeSummary& s = f.summary;
  const double t = scene.slice_thickness();
  std::ostringstream sum;
  sum << "quantity,value,unit\n"
      << "scene," << scene.name << ",\n"
      << "backend," << (scene.solver.backend == Backend::Box2D ? "box2d" : "soft") << ",\n"
      << "disks," << r.disks << ",\n"
      << "slice_thickness," << fmt(t) << ",m\n"
      << "simulated_time," << fmt(s.time_s) << ",s\n"
      << "power_per_m," << fmt(f.power_kW_per_m) << ",kW/m\n"
      << "power_per_mill," << fmt(f.power_kW_per_m * scene.mill.length_m) << ",kW\n"
      << "torque_arm_power_per_m," << fmt(f.torque_arm_kW_per_m) << ",kW/m\n"
      << "collision_power_per_m," << fmt(f.collision_kW_per_m) << ",kW/m\n"
      << "liner_dissipation_per_m," << fmt(f.liner_kW_per_m) << ",kW/m\n"
      << "solver_dissipation_per_m," << fmt(f.solver_kW_per_m) << ",kW/m\n"
      << "toe_angle," << (s.centrifuged ? "centrifuged" : fmt(s.toe_deg)) << ",deg from 6 o'clock (+ rising side)\n"
      << "shoulder_angle," << (s.centrifuged ? "centrifuged" : fmt(s.shoulder_deg)) << ",deg from 6 o'clock (+ rising side)\n"
      << "centre_of_mass_angle," << fmt(s.centre_of_mass_deg) << ",deg from 6 o'clock (+ rising side)\n"
      << "charge_mass_per_m," << fmt(s.mass_kg / t) << ",kg/m\n"
      << "packed_disks," << fmt(s.mean_packed_disks) << ",mean disks in liner contact for over a revolution\n"
      << "packed_shear_share," << fmt(s.packed_shear_share) << ",of all liner slip work (packed included)\n"
      << "escaped_disks," << s.escaped << ",\n"
      << "disk_steps_per_s," << fmt(r.window_wall_s > 0 ? r.disk_steps / r.window_wall_s : 0.0) << ",1/s\n"
      << "time_collide," << fmt(r.timing.collide_s) << ",s\n"
      << "time_solve," << fmt(r.timing.solve_s) << ",s\n"
      << "time_accounting," << fmt(r.timing.account_s) << ",s\n"
      << "wall_time," << fmt(wall_s) << ",s\n";
  io::write_file_atomic(out + "/charge_summary.csv", sum.str());

  std::ostringstream liner;
  liner << "edge,owner,owner_index,s_local_mm,x1_m,y1_m,x2_m,y2_m,shear_work_W_per_m2,"
           "impact_W_per_m2,contacts_per_s\n";
  const std::size_t n = r.mill.boundary.size();
  for (std::size_t e = 0; e < n && e < r.accounting.shear_work_J.size(); ++e) {
    const auto& info = r.mill.edges[e];
    const Vec2 a = r.mill.boundary[e], b = r.mill.boundary[(e + 1) % n];
    const double area = r.mill.edge_length_m[e] * t;
    liner << e << ',' << (info.owner == EdgeOwner::Lifter ? "lifter" : "shell") << ','
          << info.owner_index << ',' << fmt(info.s_local_m * 1e3) << ',' << fmt(a.x) << ','
          << fmt(a.y) << ',' << fmt(b.x) << ',' << fmt(b.y) << ','
          << fmt(r.accounting.shear_work_J[e] / s.time_s / area) << ','
          << fmt(r.accounting.impact_energy_J[e] / s.time_s / area) << ','
          << fmt(r.accounting.contacts[e] / s.time_s) << '\n';
  }
  io::write_file_atomic(out + "/liner_work.csv", liner.str());

  if (scene.outputs.collision_spectrum) {
    std::ostringstream spec;
    spec << "design,energy_J_lower,energy_J_upper,count_per_s,energy_W\n";
    for (int k = 0; k < kSpectrumBins; ++k)
      spec << scene.name << ',' << fmt(spectrum_bin_lower_J(k)) << ',' << fmt(spectrum_bin_lower_J(k + 1))
           << ',' << fmt(r.accounting.spectrum_count[k] / s.time_s) << ','
           << fmt(r.accounting.spectrum_energy_J[k] / s.time_s) << '\n';
    io::write_file_atomic(out + "/spectrum.csv", spec.str());
  }
  if (scene.outputs.contact_log) {
    // Liner contacts of the window (step, edge, point, impulses, velocities), SI units.
    std::ostringstream log;
    log << "step,disk,edge,x_m,y_m,nx,ny,normal_impulse_Ns,tangent_impulse_Ns,vn_before,vn_after,vt_before,vt_after\n";
    for (const ContactRecord& c : r.accounting.contact_log)
      log << c.key << ',' << c.a << ',' << c.edge << ',' << fmt(c.point_m.x) << ',' << fmt(c.point_m.y) << ','
          << fmt(c.normal.x) << ',' << fmt(c.normal.y) << ',' << fmt(c.normal_impulse) << ','
          << fmt(c.tangent_impulse) << ',' << fmt(c.vn_before) << ',' << fmt(c.vn_after) << ','
          << fmt(c.vt_before) << ',' << fmt(c.vt_after) << '\n';
    io::write_file_atomic(out + "/contacts.csv", log.str());
  }
  if (scene.outputs.snapshot) {
    // The charge and the liner at the window's end, in the world frame; the liner coloured by
    // the shear power it took over the window.
    const ChargeState& st = r.final_state;
    io::write_snapshot_table(io::snapshot_path(out, scene.name), st, scene.charge.species);
    std::vector<double> shear(n);
    for (std::size_t e = 0; e < n && e < r.accounting.shear_work_J.size(); ++e)
      shear[e] = r.accounting.shear_work_J[e] / s.time_s / (r.mill.edge_length_m[e] * t);
    io::write_liner_table(io::liner_path(out, scene.name), r.mill, st.mill_angle_rad, "shear_power_W_per_m2", shear,
                          0, 0.0, io::snapshot_marks(s, st.mill_speed_rad_s));
  }
}

std::vector<std::string> render_charge_figures(const std::string& out, const Scene& scene) {
  return plots::render_all_figures(out, {scene.name});
}

}  // namespace millwear
