// The files of `millwear charge` (see charge_outputs.hpp).
#include "study/charge_outputs.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>

#include "common/errors.hpp"
#include "common/units.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/run_folder.hpp"
#include "metrics/batch_means.hpp"
#include "metrics/trajectories.hpp"
#include "plots/plots.hpp"
#include "study/stage_files.hpp"
#include "study/vtk_output.hpp"
#include "wear/archard.hpp"
#include "wear/window.hpp"

namespace millwear {

namespace {

std::string fmt(double v) { return io::format_number(v); }

// The rows of charge_summary.csv with Morrell's C-model and Austin's SAG equation for this
// mill and charge: analytic powers, toe and shoulder to set the window's against. A model
// with no estimate for the scene (Morrell at or above critical speed or far below working
// speed, Austin at or above critical speed or for a charge without rock) has no rows: every figure written is a real one.
std::string power_model_rows(const ChargeEstimates& e) {
  std::ostringstream rows;
  const MorrellResult& m = e.morrell;
  if (std::isfinite(m.net_power_kW))
    rows << "morrell_power_per_m," << fmt(m.net_power_kW) << ",kW/m (Morrell's C-model; dry; this bed's bulk density)\n"
         << "morrell_toe_angle," << fmt(m.toe_deg_from_bottom) << ",deg from 6 o'clock (+ rising side)\n"
         << "morrell_shoulder_angle," << fmt(m.shoulder_deg_from_bottom) << ",deg from 6 o'clock (+ rising side)\n";
  if (std::isfinite(e.austin_W_per_m))
    rows << "austin_power_per_m," << fmt(e.austin_W_per_m / 1000.0) << ",kW/m (Austin's SAG power equation; porosity "
         << fmt(AustinInput{}.porosity) << "; " << fmt(100.0 * AustinInput{}.solids_mass_fraction) << "% solids)\n";
  return rows.str();
}

// With outputs.contact_log: how much of the window contacts.csv holds (the log keeps at most
// its limit of records, the window's first ones).
std::string contact_log_rows(const Scene& scene, const ChargeRunResult& r) {
  if (!scene.outputs.contact_log) return "";
  const Accounting& a = r.accounting;
  const double until_s = a.contact_log_time_s > 0.0 ? a.contact_log_time_s : a.time_s;
  return "contact_log_records," + std::to_string(a.contact_log.size()) + ",in contacts.csv (at most " +
         std::to_string(a.options.contact_log_limit) + ")\n" + "contact_log_until," + fmt(until_s) +
         ",s of the window's " + fmt(a.time_s) + " s that contacts.csv covers\n";
}

// The rows of charge_summary.csv on the flights from the lifters: their rate, their impact
// power, and the shares of it above the toe and on the bare liner there, with batch-means
// errors ("centrifuged" where there is no toe, "none" without a landed flight).
std::string impact_rows(const Scene& scene, const ChargeRunResult& r, const ImpactSummary& im) {
  const ChargeSummary& s = r.figures.summary;
  const double per_m = 1e-3 / scene.slice_thickness();
  const auto share = [&](double v) {
    return s.centrifuged ? std::string("centrifuged") : im.window.impacts == 0 ? std::string("none") : fmt(v);
  };
  const auto share_se = [&](const BatchMeans& b) {
    return s.centrifuged || im.window.impacts == 0 ? std::string("") : fmt(b.sem);
  };
  const std::string se_unit = "standard error (batch means over " + std::to_string(r.batches.size()) +
                              " sub-windows; a lower bound)";
  std::ostringstream o;
  o << "flights_per_s," << fmt(s.time_s > 0 ? static_cast<double>(im.window.impacts) / s.time_s : 0.0)
    << ",flights from the lifters landed per second (in the slice)\n"
    << "impact_power_per_m," << fmt(s.time_s > 0 ? im.window.energy_J / s.time_s * per_m : 0.0)
    << ",kW/m (first-impact energy of those flights)\n"
    << "impact_above_toe_share," << share(im.window.above_toe_share)
    << ",of the first-impact energy landing above the toe (on the liner or the charge)\n"
    << "impact_above_toe_share_se," << share_se(im.above_toe_share) << "," << se_unit << "\n"
    << "liner_impact_share," << share(im.window.liner_share)
    << ",of the first-impact energy landing on the bare liner above the toe\n"
    << "liner_impact_share_se," << share_se(im.liner_share) << "," << se_unit << "\n";
  return o.str();
}

// The species' names as column suffixes: as the scene names them, a repeated name with its
// index after it.
std::vector<std::string> species_labels(const Scene& scene) {
  std::vector<std::string> out;
  for (std::size_t k = 0; k < scene.charge.species.size(); ++k) {
    std::string name = scene.charge.species[k].name;
    if (std::find(out.begin(), out.end(), name) != out.end()) name += "_" + std::to_string(k);
    out.push_back(name);
  }
  return out;
}

// impacts.csv: the first impacts binned by angle, every species and each alone.
void write_impacts_csv(const std::string& path, const Scene& scene, const ChargeRunResult& r) {
  const int species = static_cast<int>(scene.charge.species.size());
  const ImpactDistribution d = bin_impacts(r.impacts, species);
  const double t = r.figures.summary.time_s;
  const double per_s = t > 0.0 ? 1.0 / t : 0.0;
  const double per_m = per_s / scene.slice_thickness();
  std::vector<std::string> header{"angle_deg_lower", "angle_deg_upper", "impacts_per_s", "impact_power_W_per_m",
                                  "liner_impact_power_W_per_m"};
  for (const std::string& name : species_labels(scene)) {
    header.push_back("impacts_per_s_" + name);
    header.push_back("impact_power_W_per_m_" + name);
  }
  io::CsvTable table(header);
  for (int k = 0; k < kImpactBins; ++k) {
    const auto b = static_cast<std::size_t>(k);
    std::vector<double> values{-180.0 + k * kImpactBinDeg, -180.0 + (k + 1) * kImpactBinDeg, d.count[b] * per_s,
                               d.energy_J[b] * per_m, d.liner_energy_J[b] * per_m};
    for (int sp = 0; sp < species; ++sp) {
      values.push_back(d.species_count[static_cast<std::size_t>(sp)][b] * per_s);
      values.push_back(d.species_energy_J[static_cast<std::size_t>(sp)][b] * per_m);
    }
    table.add_row(std::vector<io::CsvCell>(values.begin(), values.end()));
  }
  table.write(path);
}

// trajectories_NAME.csv: the flight paths, world frame, one block of rows per path (a blank
// line between blocks, so gnuplot draws each path apart); `end` marks a landed path's impact.
void write_trajectories_csv(const std::string& path, const ChargeRunResult& r) {
  std::ostringstream o;
  o << "path,disk,species,landed,end,x_m,y_m\n";
  for (std::size_t p = 0; p < r.flight_paths.size(); ++p) {
    const FlightPath& f = r.flight_paths[p];
    if (p) o << "\n";
    for (std::size_t k = 0; k < f.points_m.size(); ++k)
      o << p << ',' << f.disk << ',' << f.species << ',' << (f.landed ? 1 : 0) << ','
        << (f.landed && k + 1 == f.points_m.size() ? 1 : 0) << ',' << fmt(f.points_m[k].x) << ','
        << fmt(f.points_m[k].y) << '\n';
  }
  io::write_file_atomic(path, o.str());
}

}  // namespace

ChargeEstimates charge_estimates(const Scene& scene, const ChargeRunResult& r) {
  const ChargeSummary& s = r.figures.summary;
  ChargeEstimates e;
  e.morrell = morrell_estimate(scene, s);
  e.austin_W_per_m = austin_estimate_W_per_m(scene);
  e.impacts = summarize_impacts(r.impacts, static_cast<int>(r.batches.size()), s.toe_deg, s.shoulder_deg,
                                s.centrifuged);
  return e;
}

// Files of a charge run: summary, shear work along the liner, spectrum, snapshot.

std::vector<std::string> write_charge_outputs(const std::string& out, const Scene& scene, const ChargeRunResult& r,
                                              const ChargeEstimates& estimates, double wall_s) {
  std::vector<std::string> files;
  const auto write = [&files](const std::string& path, const std::string& text) {
    io::write_file_atomic(path, text);
    files.push_back(path);
  };
  const ChargeFigures& f = r.figures;
  const ChargeSummary& s = f.summary;
  const double t = scene.slice_thickness();
  std::ostringstream sum;
  sum << "quantity,value,unit\n"
      << "scene," << scene.name << ",\n";
  for (const std::string& o : scene.overrides) sum << "set," << io::quote_field(o) << ",over the scene file\n";
  sum
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
      << "energy_change_per_m," << fmt(s.kinetic_change_W * 1e-3 / t) << ",kW/m (kinetic and potential; steady: near 0)\n"
      << "toe_angle," << (s.centrifuged ? "centrifuged" : fmt(s.toe_deg)) << ",deg from 6 o'clock (+ rising side)\n"
      << "shoulder_angle," << (s.centrifuged ? "centrifuged" : fmt(s.shoulder_deg)) << ",deg from 6 o'clock (+ rising side)\n"
      << "centre_of_mass_angle," << fmt(s.centre_of_mass_deg) << ",deg from 6 o'clock (+ rising side)\n"
      << power_model_rows(estimates)
      << "charge_mass_per_m," << fmt(s.mass_kg / t) << ",kg/m\n"
      << "packed_disks," << fmt(s.mean_packed_disks) << ",mean disks in liner contact for over a revolution\n"
      << "packed_shear_share," << fmt(s.packed_shear_share) << ",of all liner slip work (packed included)\n"
      << impact_rows(scene, r, estimates.impacts)
      << contact_log_rows(scene, r)
      << "escaped_disks," << s.escaped << ",in the measured window\n"
      << "lost_disks," << r.lost_disks << ",since the fill (settling and spin-up included); any fails the run\n"
      << "disk_steps_per_s," << fmt(r.window_wall_s > 0 ? r.disk_steps / r.window_wall_s : 0.0) << ",1/s\n"
      << "time_collide," << fmt(r.timing.collide_s) << ",s\n"
      << "time_solve," << fmt(r.timing.solve_s) << ",s\n"
      << "time_accounting," << fmt(r.timing.account_s) << ",s\n"
      << "wall_time," << fmt(wall_s) << ",s\n";
  write(out + "/charge_summary.csv", sum.str());

  std::ostringstream liner;
  liner << "edge,owner,owner_index,s_local_mm,x1_m,y1_m,x2_m,y2_m,shear_work_W_per_m2,"
           "impact_W_per_m2,contacts_per_s\n";
  const std::size_t n = r.mill.boundary.size();
  for (std::size_t e = 0; e < n && e < r.accounting.shear_work_J.size(); ++e) {
    const auto& info = r.mill.edges[e];
    const Vec2 a = r.mill.boundary[e], b = r.mill.boundary[(e + 1) % n];
    const double area = r.mill.edge_length_m[e] * t;
    liner << e << ',' << (info.owner == EdgeOwner::Lifter ? "lifter" : "shell") << ','
          << info.owner_index << ',' << fmt(in_mm(info.s_local_m)) << ',' << fmt(a.x) << ','
          << fmt(a.y) << ',' << fmt(b.x) << ',' << fmt(b.y) << ','
          << fmt(r.accounting.shear_work_J[e] / s.time_s / area) << ','
          << fmt(r.accounting.impact_energy_J[e] / s.time_s / area) << ','
          << fmt(r.accounting.contacts[e] / s.time_s) << '\n';
  }
  write(out + "/liner_work.csv", liner.str());

  if (scene.outputs.collision_spectrum) {
    std::ostringstream spec;
    spec << "design,energy_J_lower,energy_J_upper,count_per_s,energy_W\n";
    for (int k = 0; k < kSpectrumBins; ++k)
      spec << scene.name << ',' << fmt(spectrum_bin_lower_J(k)) << ',' << fmt(spectrum_bin_lower_J(k + 1))
           << ',' << fmt(r.accounting.spectrum_count[k] / s.time_s) << ','
           << fmt(r.accounting.spectrum_energy_J[k] / s.time_s) << '\n';
    write(out + "/spectrum.csv", spec.str());
  }
  if (scene.outputs.contact_log) {
    // Liner contacts of the window (step, edge, point, impulses, velocities), SI units.
    std::ostringstream log;
    log << "step,disk,edge,x_m,y_m,nx,ny,normal_impulse_Ns,tangent_impulse_Ns,vn_before,vn_after,vt_before,vt_after\n";
    for (const ContactRecord& c : r.accounting.contact_log)
      log << c.step << ',' << c.a << ',' << c.edge << ',' << fmt(c.point_m.x) << ',' << fmt(c.point_m.y) << ','
          << fmt(c.normal.x) << ',' << fmt(c.normal.y) << ',' << fmt(c.normal_impulse) << ','
          << fmt(c.tangent_impulse) << ',' << fmt(c.vn_before) << ',' << fmt(c.vn_after) << ','
          << fmt(c.vt_before) << ',' << fmt(c.vt_after) << '\n';
    write(out + "/contacts.csv", log.str());
  }
  if (scene.outputs.vtk && !r.frames.empty()) {
    // Archard's rate at the scene's C; a C given as a loss rate is calibrated on this window
    // as the wear history calibrates it on its first.
    double c = scene.wear.wear_rate_m3_per_J;
    if (scene.wear.rate_source != WearRateSource::Given) {
      std::vector<double> power(r.accounting.shear_work_J.size());
      for (std::size_t e = 0; e < power.size(); ++e) power[e] = r.accounting.shear_work_J[e] / s.time_s;
      c = real_wear_rate(scene, r.mill, power);
    }
    for (std::string& v : write_vtk_series(out + "/vtk", scene.name, scene, r.mill, r.frames,
                                           liner_fields(scene, r.mill, r.accounting, c)))
      files.push_back(std::move(v));
  }
  files.push_back(io::join_path(out, "impacts.csv"));
  write_impacts_csv(files.back(), scene, r);
  files.push_back(io::join_path(out, "trajectories_" + scene.name + ".csv"));
  write_trajectories_csv(files.back(), r);
  if (scene.outputs.snapshot) {
    // The charge and the liner at the window's end, in the world frame; the liner coloured by
    // the shear power it took over the window.
    const ChargeState& st = r.final_state;
    study::write_snapshot_table(io::snapshot_path(out, scene.name), st, scene.charge.species);
    std::vector<double> shear(n);
    for (std::size_t e = 0; e < n && e < r.accounting.shear_work_J.size(); ++e)
      shear[e] = r.accounting.shear_work_J[e] / s.time_s / (r.mill.edge_length_m[e] * t);
    study::write_liner_table(io::liner_path(out, scene.name), r.mill, st.mill_angle_rad, "shear_power_W_per_m2", shear,
                          0, 0.0, study::snapshot_marks(s, st.mill_speed_rad_s));
    files.push_back(io::snapshot_path(out, scene.name));
    files.push_back(io::liner_path(out, scene.name));
  }
  return files;
}

namespace {

// The value of a quantity in charge_summary.csv ("" if it has no such row).
std::string summary_value(const io::CsvData& summary, const std::string& quantity) {
  const std::size_t q = summary.column("quantity"), v = summary.column("value");
  for (const auto& row : summary.rows)
    if (row[q] == quantity) return row[v];
  return "";
}

// A share as a percentage with its error, for a figure's title.
std::string percent_text(const std::string& share, const std::string& se) {
  char* end = nullptr;
  const double v = std::strtod(share.c_str(), &end);
  if (share.empty() || *end != '\0') return share.empty() ? "none" : share;
  char buf[96];
  const double e = std::strtod(se.c_str(), nullptr);
  std::snprintf(buf, sizeof buf, se.empty() ? "%.1f%%" : "%.1f +- %.1f%%", 100.0 * v, 100.0 * e);
  return buf;
}

}  // namespace

std::vector<std::string> charge_output_names(const Scene& scene) {
  const std::string& n = scene.name;
  std::vector<std::string> names = {"charge_summary.csv", "liner_work.csv", "spectrum.csv", "contacts.csv",
                                    "impacts.csv", "trajectories_" + n + ".csv", "snapshot_" + n + ".csv",
                                    "liner_" + n + ".csv", "plots/data/" + n + "_spectrum.csv", "vtk/" + n + ".pvd"};
  for (const std::string& fig : {std::string("spectrum"), "snapshot_" + n, "impacts_" + n, "trajectories_" + n})
    for (const char* ext : {".png", ".svg"}) names.push_back("plots/" + fig + ext);
  return names;
}

std::vector<std::string> render_charge_figures(const std::string& out, const Scene& scene) {
  plots::FigureOutcome figures;
  try {
    figures = plots::draw_all_figures(out, {scene.name});
  } catch (const RunError& e) {  // their data could not be written: charge's own still draw
    figures.failures.push_back(e.what());
  }
  std::vector<std::string>& written = figures.written;
  std::vector<std::string>& failures = figures.failures;
  // The impact and trajectory figures: the species named and coloured as in the snapshot,
  // the toe and shoulder from charge_summary.csv.
  std::map<std::string, std::string> vars;
  std::string names, colours;
  std::vector<bool> balls;
  for (const SpeciesDef& sp : scene.charge.species) balls.push_back(sp.is_ball);
  for (const std::string& name : species_labels(scene)) names += (names.empty() ? "" : " ") + name;
  for (const std::string& c : plots::species_colours(balls)) colours += (colours.empty() ? "" : " ") + c;
  const io::CsvData summary = io::read_csv(io::join_path(out, "charge_summary.csv"));
  const std::string toe = summary_value(summary, "toe_angle");
  vars["datadir"] = out;
  vars["design"] = scene.name;
  vars["species_names"] = names;
  vars["species_colours"] = colours;
  vars["centrifuged"] = toe == "centrifuged" ? "1" : "0";
  vars["toe_deg"] = toe == "centrifuged" ? "0" : toe;
  vars["shoulder_deg"] = toe == "centrifuged" ? "0" : summary_value(summary, "shoulder_angle");
  vars["turning"] = direction_at(scene, 0.0) > 0 ? "1" : "-1";
  vars["liner_share_text"] = percent_text(summary_value(summary, "liner_impact_share"),
                                          summary_value(summary, "liner_impact_share_se"));
  vars["above_toe_share_text"] = percent_text(summary_value(summary, "impact_above_toe_share"),
                                              summary_value(summary, "impact_above_toe_share_se"));
  const std::string plots_out = io::plots_out_dir(out);
  io::ensure_dir(plots_out);
  const std::string log = io::join_path(plots_out, "gnuplot.log");
  auto draw = [&](const std::string& figure, const std::string& name) {
    std::map<std::string, std::string> v = vars;
    v["outbase"] = io::join_path(plots_out, name);
    try {
      const auto files = plots::render_figure(plots::script_path(figure), v, log);
      written.insert(written.end(), files.begin(), files.end());
    } catch (const RunError& e) {
      failures.push_back(name + ": " + e.what());
    }
  };
  draw("impacts", "impacts_" + scene.name);
  // The envelope is drawn over the snapshot (outputs.snapshot).
  if (io::file_exists(io::snapshot_path(out, scene.name)) && io::file_exists(io::liner_path(out, scene.name)))
    draw("trajectories", "trajectories_" + scene.name);
  return plots::figures_or_throw(figures);
}

}  // namespace millwear
