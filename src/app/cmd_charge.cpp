// `millwear charge SCENE -o OUT`: the charge alone (no wear) for some revolutions.
#include <CLI/CLI.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include "app/commands.hpp"
#include "app/output_folder.hpp"
#include "engine/charge_run.hpp"
#include "io/atomic_write.hpp"
#include "io/folder_lock.hpp"
#include "scene/fidelity.hpp"
#include "scene/limits.hpp"
#include "scene/scene.hpp"

namespace millwear::app {

namespace {

struct ChargeArgs {
  std::string scene;
  std::string out;
  std::string fidelity;
  double revolutions = 0.0;
  bool quiet = false;
};

std::string fmt(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

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
      << "toe_angle," << fmt(s.toe_deg) << ",deg from 6 o'clock (+ rising side)\n"
      << "shoulder_angle," << fmt(s.shoulder_deg) << ",deg from 6 o'clock (+ rising side)\n"
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
    std::ostringstream snap;
    snap << "x_m,y_m,radius_m,species\n";
    const ChargeState& st = r.final_state;
    for (std::size_t i = 0; i < st.size(); ++i)
      if (st.active[i])
        snap << fmt(st.position_m[i].x) << ',' << fmt(st.position_m[i].y) << ',' << fmt(st.radius_m[i])
             << ',' << scene.charge.species[st.species[i]].name << '\n';
    io::write_file_atomic(out + "/snapshot.csv", snap.str());
  }
}

int run_charge(const ChargeArgs& args) {
  Scene scene = load_scene(args.scene);
  if (!args.fidelity.empty()) apply_fidelity(scene, args.fidelity);
  if (args.revolutions > 0.0) scene.run.revolutions = args.revolutions;
  check_run_limits(scene, args.scene);
  const io::FolderLock lock(args.out);  // one writer per folder, for the whole run
  const auto t0 = std::chrono::steady_clock::now();
  ChargeRunResult result = run_charge_only(scene);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  write_charge_outputs(args.out, scene, result, wall);
  const ChargeFigures& f = result.figures;
  for (const auto& e : result.events) std::cerr << "millwear: warning: t=" << e.time_s << " s: " << e.what << "\n";
  std::printf("%s: %zu disks, %.1f revolutions in %.1f s wall (%.2f M disk-steps/s)\n",
              scene.name.c_str(), result.disks, scene.run.revolutions, wall,
              result.window_wall_s > 0 ? result.disk_steps / result.window_wall_s / 1e6 : 0.0);
  std::printf("  power        %10.1f kW/m   %10.1f kW per mill (torque arm: %.1f kW/m)\n",
              f.power_kW_per_m, f.power_kW_per_m * scene.mill.length_m, f.torque_arm_kW_per_m);
  std::printf("  collisions   %10.1f kW/m   liner %.1f kW/m, solver %.1f kW/m\n", f.collision_kW_per_m,
              f.liner_kW_per_m, f.solver_kW_per_m);
  std::printf("  toe %.0f deg, shoulder %.0f deg (from 6 o'clock, + on the rising side)\n",
              f.summary.toe_deg, f.summary.shoulder_deg);
  if (f.summary.mean_packed_disks > 0.0)
    std::printf("  packed: %.1f disks on average rode the liner for over a revolution; their slip, %.1f%%\n"
                "          of all liner slip work, is not counted as wear unless wear.packed_wear is set\n"
                "          (README \"Numerical limits\")\n",
                f.summary.mean_packed_disks, 100.0 * f.summary.packed_shear_share);
  std::printf("  escaped disks %lld; results in %s\n", static_cast<long long>(f.summary.escaped),
              args.out.c_str());
  // A disk lost at any time (settling and spin-up included) makes every figure suspect.
  if (result.lost_disks > 0) {
    std::cerr << "millwear: run failed: " << result.lost_disks << " of " << result.disks
              << " disks were lost (escaped or non-finite; first: t=" << result.events.front().time_s
              << " s: " << result.events.front().what << ")\n";
    return 1;
  }
  return 0;
}

}  // namespace

void register_charge(CLI::App& app, Action* action) {
  auto args = std::make_shared<ChargeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "charge", "Run the charge alone (no wear): power, toe/shoulder, shear work along the liner");
  cmd->add_option("scene", args->scene, "scene file (TOML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", args->out, "output folder")->required()->check(output_folder());
  cmd->add_option("--fidelity", args->fidelity, "draft | standard | reference");
  cmd->add_option("--revolutions", args->revolutions, "measured revolutions (default: the scene's)")
      ->check(CLI::Range(1e-6, 1e4));
  cmd->callback([args, action] { *action = [args] { return run_charge(*args); }; });
}

}  // namespace millwear::app
