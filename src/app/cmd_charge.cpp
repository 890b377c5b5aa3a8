// `millwear charge SCENE -o OUT`: the charge alone (no wear) for some revolutions.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <unistd.h>

#include "app/commands.hpp"
#include "app/fidelity_option.hpp"
#include "app/number_checks.hpp"
#include "app/output_folder.hpp"
#include "app/plain_progress.hpp"
#include "app/set_option.hpp"
#include "app/signals.hpp"
#include "app/threads_option.hpp"
#include "common/text.hpp"
#include "io/csv.hpp"
#include "io/folder_lock.hpp"
#include "io/run_folder.hpp"
#include "io/staging.hpp"
#include "metrics/trajectories.hpp"
#include "millwear_commit.hpp"  // generated at build time: MILLWEAR_COMMIT
#include "plots/plots.hpp"
#include "scene/fidelity.hpp"
#include "scene/filling.hpp"
#include "scene/limits.hpp"
#include "scene/scene.hpp"
#include "study/charge_outputs.hpp"
#include "study/charge_run.hpp"
#include "study/command_manifest.hpp"
#include "study/plan.hpp"
#include "wear/reshape.hpp"

namespace millwear::app {

namespace {

struct ChargeArgs {
  std::string scene;
  std::string out;
  std::string fidelity;
  double revolutions = 0.0;
  int threads = 0;
  bool vtk = false;
  bool check = false;
  bool quiet = false;
  std::vector<std::string> overrides;
};

// An earlier charge's folder is this one's to rewrite, but not a user's file in it under a name
// this charge writes (another scene's snapshot, a contact log), nor a folder under such a name,
// which no file can replace: refused, before anything is run.
void refuse_users_file(const std::string& out, const Scene& scene) {
  std::vector<std::string> names = charge_output_names(scene);
  names.push_back("manifest.json");
  io::check_output_names(out, names, "charge");
  // Nor an input among them, or among the earlier charge's files it deletes once it is done.
  std::vector<std::string> taken = names;
  for (const std::string& f : io::manifest_files(out)) taken.push_back(f);
  io::check_inputs_not_among(out, taken, study::scene_input_files(scene), "charge");
  if (const std::string taken = io::unlisted_output(out, charge_output_names(scene)); !taken.empty())
    throw InputError(out, "-o",
                     "a folder that is new or holds an earlier charge's results, but " + taken +
                         " is there and no charge wrote it (its manifest.json does not list it); this charge would "
                         "overwrite it: move it, or use another folder");
}

int run_charge(const ChargeArgs& args) {
  refuse_sets_options_give(args.overrides, {{"fidelity", "--fidelity", !args.fidelity.empty()},
                                            {"run.revolutions", "--revolutions", args.revolutions > 0.0}});
  std::vector<std::string> overrides = args.overrides;
  if (args.vtk) overrides.push_back("outputs.vtk=true");
  Scene scene = study::load_checked_scene(args.scene, overrides, args.fidelity, [&args](Scene& s) {
    if (args.revolutions > 0.0) s.run.revolutions = args.revolutions;
    s.solver.threads = step_threads(args.threads);
    s.solver.threads_fit_size = args.threads == 0;
  });
  // What is about to run, before the run: a charge of a million disks (a mill diameter in mm
  // written as m) shows itself here, not after hours of silence.
  char plan[256];
  std::snprintf(plan, sizeof plan, "%s: about %.0f disks, fidelity %s, %g revolutions measured after settling",
                scene.name.c_str(), expected_charge_disks(scene), scene.fidelity.c_str(), scene.run.revolutions);
  if (args.check) {
    // What the lock would refuse, found without taking it.
    io::check_output_folder(args.out);
    std::error_code ec;
    if (std::filesystem::is_directory(args.out, ec)) io::check_folder_not_taken(args.out, "charge");
    refuse_users_file(args.out, scene);
    std::printf("%s\n", plan);
    for (const std::string& note : distribution_notes(scene)) std::printf("  %s\n", note.c_str());
    for (const std::string& note : limit_notes(scene)) std::printf("  %s\n", note.c_str());
    return 0;
  }
  const io::FolderLock lock(args.out, "charge");  // one writer per folder, for the whole run
  refuse_users_file(args.out, scene);
  // Ctrl-C or SIGTERM ends the charge at once (exit 128 + signal), first saying what it leaves;
  // heard from before the staging folder is made, so that no stop goes unreported.
  g_stop_note = "millwear charge: interrupted; nothing of this charge is kept, " + args.out +
                " is as it was (an earlier charge's results in it stay): run the charge again\n";
  const SignalScope stop(note_and_die);
  // The new files are drawn up beside an earlier charge's, which stay in OUT as they were
  // until every new file is complete (a charge that fails or is stopped leaves them); then
  // the earlier charge's files that no new one replaces go (its manifest's list).
  io::StagedOutputs staged(args.out);
  if (!args.quiet) std::fprintf(stderr, "millwear charge: %s\n", plan);
  if (!args.quiet)
    for (const std::string& note : limit_notes(scene)) std::fprintf(stderr, "  %s\n", note.c_str());
  const auto t0 = std::chrono::steady_clock::now();
  // A line every few seconds on a terminal, every minute in a log: a long charge is not silent.
  const double every_s = ::isatty(STDERR_FILENO) ? 5.0 : kProgressEveryS;
  double last_s = 0.0;
  const auto progress = [&](const ChargeProgress& p) {
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (wall_s - last_s < every_s) return;
    last_s = wall_s;
    std::fprintf(stderr, "millwear charge: %s  %s, %.3g of %.3g s simulated, %s wall\n", clock_text().c_str(),
                 p.phase, p.done_s, p.of_s, duration_text(wall_s).c_str());
  };
  ChargeRunResult result = args.quiet ? run_charge_only(scene) : run_charge_only(scene, progress);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const ChargeEstimates est = charge_estimates(scene, result);
  study::CommandRecord record{"charge", MILLWEAR_COMMIT, args.scene, scene.overrides, scene.fidelity,
                              scene.solver.seed, {{"revolutions", io::format_number(scene.run.revolutions)}}, {}};
  record.files = write_charge_outputs(staged.dir(), scene, result, est, wall);
  const ChargeFigures& f = result.figures;
  for (const auto& e : result.events) std::cerr << "millwear: warning: t=" << e.time_s << " s: " << e.what << "\n";
  std::printf("%s: %zu disks, %g revolutions in %.1f s wall (%.2f M disk-steps/s)\n",
              scene.name.c_str(), result.disks, scene.run.revolutions, wall,
              result.window_wall_s > 0 ? result.disk_steps / result.window_wall_s / 1e6 : 0.0);
  // Four significant digits: a lab mill turning slowly draws some 0.02 kW/m, a SAG mill 2000.
  std::printf("  power        %10.4g kW/m   %10.4g kW per mill (torque arm: %.4g kW/m)\n",
              f.power_kW_per_m, f.power_kW_per_m * scene.mill.length_m, f.torque_arm_kW_per_m);
  std::printf("  collisions   %10.4g kW/m   liner %.4g kW/m, solver %.4g kW/m\n", f.collision_kW_per_m,
              f.liner_kW_per_m, f.solver_kW_per_m);
  const MorrellResult& morrell = est.morrell;
  if (std::isfinite(morrell.net_power_kW))
    std::printf("  Morrell      %10.4g kW/m   toe %.0f deg, shoulder %.0f deg (C-model, dry, this bed's density)\n",
                morrell.net_power_kW, whole_degrees(morrell.toe_deg_from_bottom),
                whole_degrees(morrell.shoulder_deg_from_bottom));
  else if (!(scene.mill.speed_fraction_critical < 1.0))
    std::printf("  Morrell      none at or above critical speed (the C-model's fits end below it)\n");
  else
    std::printf("  Morrell      none at %.3g%% of critical speed (the C-model's fitted toe and shoulder hold no "
                "charge of this filling there; its fits cover working speeds)\n",
                100.0 * scene.mill.speed_fraction_critical);
  const double austin_W_per_m = est.austin_W_per_m;
  if (std::isfinite(austin_W_per_m))
    std::printf("  Austin       %10.4g kW/m   (SAG power equation; porosity %.2g, %.0f%% solids)\n",
                austin_W_per_m / 1000.0, AustinInput{}.porosity, 100.0 * AustinInput{}.solids_mass_fraction);
  else
    std::printf("  Austin       none (a SAG model: rock in the charge, below critical speed)\n");
  if (const std::string unsteady = unsteady_window(f.summary); !unsteady.empty())
    std::cerr << "millwear: warning: " << unsteady << "\n";
  if (const std::string unsound = unsound_energy_split(f); !unsound.empty())
    std::cerr << "millwear: warning: " << unsound << "\n";
  // contacts.csv keeps the window's first records only: say where it stops.
  if (scene.outputs.contact_log && result.accounting.contact_log_time_s > 0.0)
    std::cerr << "millwear: warning: contacts.csv holds the window's first " << result.accounting.contact_log.size()
              << " liner contacts, its first " << result.accounting.contact_log_time_s << " s of "
              << result.accounting.time_s << " s (the log keeps at most that many; charge_summary.csv: "
                 "contact_log_until)\n";
  const double com_deg = f.summary.centre_of_mass_deg;
  if (f.summary.centrifuged)
    std::printf("  centrifuged: the charge covers the whole shell (no toe or shoulder); centre of mass %.0f deg\n",
                whole_degrees(com_deg));
  else
    std::printf("  toe %.0f deg, shoulder %.0f deg, centre of mass %.0f deg (from 6 o'clock, + on the rising side)\n",
                whole_degrees(f.summary.toe_deg), whole_degrees(f.summary.shoulder_deg), whole_degrees(com_deg));
  if (f.summary.mean_packed_disks > 0.0)
    std::printf("  packed: %.1f disks on average rode the liner for over a revolution; their slip, %.1f%%\n"
                "          of all liner slip work, is not counted as wear unless wear.packed_wear is set\n"
                "          (README \"Numerical limits\")\n",
                f.summary.mean_packed_disks, 100.0 * f.summary.packed_shear_share);
  const ImpactSummary& im = est.impacts;
  const double flights_per_s = f.summary.time_s > 0 ? static_cast<double>(im.window.impacts) / f.summary.time_s : 0.0;
  if (im.window.impacts == 0)
    std::printf("  flights      none from the lifters landed in the window\n");
  else if (f.summary.centrifuged)
    std::printf("  flights      %.1f/s from the lifters (slice); centrifuged: no toe to set their impacts against\n",
                flights_per_s);
  else
    std::printf("  flights      %.1f/s from the lifters (slice); of their impact energy %.1f +- %.1f%% lands above\n"
                "               the toe, %.1f +- %.1f%% on the bare liner there (impacts.csv, docs/trajectories.md)\n",
                flights_per_s, 100.0 * im.window.above_toe_share, 100.0 * im.above_toe_share.sem,
                100.0 * im.window.liner_share, 100.0 * im.liner_share.sem);
  std::printf("  lost disks %lld since the fill (%lld escaped in the window); results in %s\n",
              static_cast<long long>(result.lost_disks), static_cast<long long>(f.summary.escaped),
              args.out.c_str());
  bool figures_failed = false;
  try {
    const auto figs = render_charge_figures(staged.dir(), scene);
    record.files.insert(record.files.end(), figs.begin(), figs.end());
    // The figures drawn, by name: those of an output the scene turns off (outputs.snapshot,
    // outputs.collision_spectrum) are not.
    std::vector<std::string> names;
    for (const std::string& f : figs) {
      const std::filesystem::path p(f);
      if (p.extension() != ".png" && p.extension() != ".svg") continue;
      if (std::find(names.begin(), names.end(), p.stem().string()) == names.end()) names.push_back(p.stem().string());
    }
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    if (!names.empty()) std::printf("  figures in %s/plots (%s)\n", args.out.c_str(), list.c_str());
  } catch (const std::exception& e) {
    std::cerr << "millwear: warning: figures: " << staged.in_out_text(e.what()) << "\n";
    figures_failed = plots::gnuplot_available();  // without gnuplot the results stand alone
  }
  for (const std::string& f : plots::figure_data_files(staged.dir(), {scene.name})) record.files.push_back(f);
  // A disk lost at any time (settling and spin-up included) makes every figure suspect: the
  // files stay for a look at what happened, and the manifest says the run failed.
  std::string failure;
  if (result.lost_disks > 0) {
    char why[512];
    std::snprintf(why, sizeof why, "%lld of %lld disks were lost (escaped or non-finite; first: t=%g s: %s)",
                  static_cast<long long>(result.lost_disks), static_cast<long long>(result.disks),
                  result.events.front().time_s, result.events.front().what.c_str());
    failure = why;
  }
  study::write_command_manifest(staged.dir(), record, failure);
  // A charge that lost disks is moved in too: its files are there for a look at what
  // happened, and its manifest says that it failed.
  staged.commit({args.scene});
  if (!failure.empty()) {
    std::cerr << "millwear: run failed: " << failure << "\n";
    return 1;
  }
  return figures_failed ? 1 : 0;
}

}  // namespace

void register_charge(CLI::App& app, Action* action) {
  auto args = std::make_shared<ChargeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "charge", "Run the charge alone (no wear): power, toe/shoulder, shear work along the liner");
  cmd->add_option("scene", args->scene, "scene file (TOML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("-o,--out", args->out, "output folder")->required()->check(output_folder());
  cmd->add_option("--fidelity", args->fidelity, "draft | standard | reference")->check(fidelity_name());
  add_threads_option(cmd, args->threads);
  cmd->add_option("--revolutions", args->revolutions, "measured revolutions (default: the scene's)")
      ->check(finite_in(1e-6, 1e4));
  add_set_option(cmd, &args->overrides);
  cmd->add_flag("--vtk", args->vtk, "ParaView files of the measured window in OUT/vtk/ (as --set outputs.vtk=true)");
  cmd->add_flag("--check", args->check, "validate the scene, print the disks it will hold, run nothing");
  cmd->add_flag("-q,--quiet", args->quiet, "no line before the run, only the results");
  cmd->callback([args, action] { *action = [args] { return run_charge(*args); }; });
}

}  // namespace millwear::app
