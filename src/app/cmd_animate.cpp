// `millwear animate SCENE -o FILE.gif`: a few seconds of the charge tumbling, for a lecture.
//
// Without --history the liner is coloured by the shear work rate it takes during the
// animated seconds (W/m^2). With --history OUT (a folder of `millwear run` holding this
// scene's design) the animation walks through the finished stages: each stage's worn
// liner in turn (set_liner, the charge keeps moving), coloured by that stage's wear rate
// (mm per 1000 h, the rates behind OUT/liner_DESIGN.csv). Frames go to plots/animate.gp.
#include <CLI/CLI.hpp>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "common/units.hpp"
#include "app/commands.hpp"
#include "io/stage_files.hpp"
#include "common/errors.hpp"
#include "engine/charge_run.hpp"
#include "engine/engine.hpp"
#include "io/atomic_write.hpp"
#include "io/run_folder.hpp"
#include "plots/plots.hpp"
#include "scene/fidelity.hpp"
#include "scene/limits.hpp"
#include "scene/scene.hpp"

namespace millwear::app {

namespace fs = std::filesystem;

namespace {


struct AnimateArgs {
  std::string scene;
  std::string out;
  std::string history;
  std::string fidelity;
  double seconds = 3.0;
  int frames = 60;
  int size = 640;
  bool keep_data = false;
};

// One stretch of the animation on one liner.
struct Segment {
  MillGeometry mill;
  std::vector<double> edge_value;  // colour per boundary edge (history: mm/1000 h)
  int stage = 0;
  double hours = 0.0;
};

struct Frame {
  std::vector<Vec2> position;
  std::vector<double> radius;
  std::vector<int> species;
  double mill_angle = 0.0, time_s = 0.0, speed = 0.0;
  std::size_t segment = 0;
};

std::string fmt(double v, const char* f = "%.6g") {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

std::string gp_string(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

// Direction of rotation at an operating time (bidirectional: reverses every reverse_every).
double direction_at_hours(const Scene& scene, double hours) {
  if (scene.mill.direction == Direction::Reverse) return -1.0;
  if (scene.mill.direction == Direction::Forward) return 1.0;
  const double period = scene.mill.reverse_every_hours;
  if (!(period > 0)) return 1.0;
  const long n = static_cast<long>(std::floor(hours / period + 1e-9));
  return n % 2 == 0 ? 1.0 : -1.0;
}

int run_animate(const AnimateArgs& args) {
  Scene scene = load_scene(args.scene);
  if (!args.fidelity.empty()) apply_fidelity(scene, args.fidelity);
  check_run_limits(scene, args.scene);  // before anything is filled or written
  if (args.out.size() < 5 || args.out.substr(args.out.size() - 4) != ".gif")
    throw InputError("", "-o", "an output file name ending in .gif, found '" + args.out + "'");
  const std::string outbase = args.out.substr(0, args.out.size() - 4);
  const double R = scene.radius_m();

  // The liners to show.
  std::vector<Segment> segments;
  std::string cblabel;
  if (!args.history.empty()) {
    const int last = io::last_finished_stage(args.history, scene.name);
    if (last < 0)
      throw InputError(args.history, "--history",
                       "a `millwear run` output folder with finished stages of design '" +
                           scene.name + "' (no " + scene.name + "_stage0.done in " +
                           io::stages_dir(args.history) + ")");
    for (int k = 0; k <= last; ++k) {
      StageRecord rec = io::read_stage_state(args.history, scene.name, k);
      if (rec.units.empty() || rec.edge_wear_rate_m_per_s.empty()) continue;  // worn-out marker
      Segment s;
      s.mill = build_mill(R, scene.mill.rows, rec.units);
      s.edge_value = rec.edge_wear_rate_m_per_s;
      for (double& v : s.edge_value) v = mm_per_1000h(v);
      s.edge_value.resize(s.mill.boundary.size(), 0.0);
      s.stage = k;
      s.hours = rec.hours;
      segments.push_back(std::move(s));
    }
    if (segments.empty())
      throw InputError(args.history, "--history", "stages with a liner and wear rates");
    cblabel = "Liner wear rate (mm per 1000 h)";
  } else {
    Segment s;
    s.mill = build_scene_mill(scene);
    segments.push_back(std::move(s));
    cblabel = "Liner shear work rate (W/m^2)";
  }

  // Simulate: settle, spin up, then record frames evenly over the animated seconds.
  const auto t0 = std::chrono::steady_clock::now();
  const ChargeState initial = fill_charge(scene, segments.front().mill);
  auto engine = make_engine(scene, segments.front().mill, initial, accounting_options_for(scene));
  double dir = direction_at_hours(scene, segments.front().hours);
  settle_and_spin_up(*engine, scene, dir);
  engine->reset_window();
  const double start_s = engine->state().time_s;
  const int nframes = args.frames;
  const int steps_per_frame = std::max(1, steps_for(args.seconds / nframes, engine->time_step_s()));
  std::vector<Frame> frames;
  frames.reserve(static_cast<std::size_t>(nframes));
  std::size_t seg = 0;
  for (int f = 0; f < nframes; ++f) {
    const std::size_t want = std::min(segments.size() - 1,
                                      static_cast<std::size_t>(f) * segments.size() / static_cast<std::size_t>(nframes));
    if (want != seg) {
      seg = want;
      engine->set_liner(segments[seg].mill);
      const double d = direction_at_hours(scene, segments[seg].hours);
      if (d != dir) {
        dir = d;
        engine->set_mill_speed(dir * scene.angular_speed_rad_s());
      }
    }
    engine->step(steps_per_frame);
    const ChargeState& st = engine->state();
    Frame fr;
    for (std::size_t i = 0; i < st.size(); ++i) {
      if (!st.active[i]) continue;
      fr.position.push_back(st.position_m[i]);
      fr.radius.push_back(st.radius_m[i]);
      fr.species.push_back(st.species[i]);
    }
    fr.mill_angle = st.mill_angle_rad;
    fr.time_s = st.time_s - start_s;  // animated seconds
    fr.speed = st.mill_speed_rad_s;
    fr.segment = seg;
    frames.push_back(std::move(fr));
  }
  if (args.history.empty()) {
    // Shear work rate per unit liner area over the animated window.
    const Accounting& acc = engine->accounting();
    Segment& s = segments.front();
    s.edge_value.assign(s.mill.boundary.size(), 0.0);
    const double t = scene.slice_thickness();
    for (std::size_t e = 0; e < s.edge_value.size() && e < acc.shear_work_J.size(); ++e)
      s.edge_value[e] = acc.time_s > 0 ? acc.shear_work_J[e] / acc.time_s / (s.mill.edge_length_m[e] * t) : 0.0;
  }
  // Colour scale to the 98th percentile: a few hot edges (a lifter's leading corner) would
  // otherwise leave the rest of the liner one colour. Hotter edges show at the top colour.
  std::vector<double> all;
  for (const auto& s : segments)
    for (double v : s.edge_value)
      if (std::isfinite(v) && v > 0) all.push_back(v);
  double cbmax = 1.0;
  if (!all.empty()) {
    const std::size_t k = std::min(all.size() - 1, static_cast<std::size_t>(0.98 * all.size()));
    std::nth_element(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(k), all.end());
    if (all[k] > 0) cbmax = all[k];
  }

  // Data and meta files for the script.
  const fs::path work = args.keep_data
                            ? fs::path(outbase + "_frames")
                            : fs::temp_directory_path() / ("millwear-animate-" + std::to_string(::getpid()));
  fs::create_directories(work);
  std::string data;
  data.reserve(frames.size() * 8000);
  std::ostringstream meta;
  meta << "nframes = " << frames.size() << "\nR = " << fmt(R, "%.17g") << "\ncbmax = " << fmt(cbmax, "%.17g")
       << "\ncblabel = " << gp_string(cblabel) << "\narray ftitle[" << frames.size() << "]\n";
  for (std::size_t f = 0; f < frames.size(); ++f) {
    const Frame& fr = frames[f];
    const Segment& s = segments[fr.segment];
    if (f) data += "\n\n";
    for (std::size_t i = 0; i < fr.position.size(); ++i)
      data += fmt(fr.position[i].x) + " " + fmt(fr.position[i].y) + " " + fmt(fr.radius[i]) + " " +
              std::to_string(fr.species[i]) + "\n";
    if (fr.position.empty()) data += "0 0 0 0\n";
    data += "\n\n";
    const std::size_t n = s.mill.boundary.size();
    // One closed path; each vertex carries the value of the edge it starts. (A path, not
    // one vector per edge: gnuplot drops vectors shorter than a pixel, leaving gaps.)
    for (std::size_t e = 0; e <= n; ++e) {
      const Vec2 a = rotated(s.mill.boundary[e % n], fr.mill_angle);
      data += fmt(a.x) + " " + fmt(a.y) + " " + fmt(s.edge_value[e % n]) + "\n";
    }
    const double rpm = std::fabs(fr.speed) * 60.0 / (2.0 * kPi);
    std::string title = scene.name + "   t = " + fmt(fr.time_s, "%.2f") + " s   " + fmt(rpm, "%.1f") +
                        " rpm " + (fr.speed >= 0 ? "(counter-clockwise)" : "(clockwise)");
    if (!args.history.empty())
      title += "\\nliner after stage " + std::to_string(s.stage) + " (" + fmt(s.hours, "%.0f") + " h)";
    meta << "ftitle[" << f + 1 << "] = " << "\"" << [&] {
      std::string q;
      for (char c : title) {
        if (c == '"') q += '\\';
        q += c;
      }
      return q;
    }() << "\"\n";
  }
  const std::string datafile = (work / "frames.dat").string(), metafile = (work / "frames_meta.gp").string();
  io::write_file_atomic(datafile, data);
  io::write_file_atomic(metafile, meta.str());

  const int delay = std::max(2, static_cast<int>(std::lround(100.0 * args.seconds / nframes)));
  const std::string log = (work / "gnuplot.log").string();
  const fs::path parent = fs::path(args.out).parent_path();
  if (!parent.empty()) io::ensure_dir(parent.string());
  try {
    plots::render_figure(plots::script_path("animate"),
                         {{"datafile", datafile}, {"metafile", metafile}, {"outbase", outbase},
                          {"formats", "gif"}, {"delay", std::to_string(delay)},
                          {"size", std::to_string(args.size)}},
                         log);
  } catch (...) {
    if (!args.keep_data) {
      std::error_code ec;
      fs::remove_all(work, ec);
    }
    throw;
  }
  if (!args.keep_data) {
    std::error_code ec;
    fs::remove_all(work, ec);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("%s: %zu frames, %.2f s of the charge (%zu disks), %s; wrote %s in %.1f s\n",
              scene.name.c_str(), frames.size(), args.seconds, initial.size(),
              args.history.empty() ? "liner by shear work rate"
                                   : ("stages 0-" + std::to_string(segments.back().stage) + " by wear rate").c_str(),
              args.out.c_str(), wall);
  if (args.keep_data) std::printf("  frame data kept in %s (rerun plots/animate.gp by hand)\n", work.string().c_str());
  return 0;
}

}  // namespace

void register_animate(CLI::App& app, Action* action) {
  auto args = std::make_shared<AnimateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "animate", "Animated GIF of the charge tumbling, the liner coloured by wear rate (teaching demo)");
  cmd->footer(
      "Without --history the liner is coloured by its shear work rate (W/m^2) in the animated\n"
      "seconds. With --history OUT (a `millwear run` folder holding this scene's design) the\n"
      "animation steps through the finished stages' worn liners, coloured by wear rate\n"
      "(mm per 1000 h). Needs gnuplot with the gif terminal.");
  cmd->add_option("scene", args->scene, "scene file (TOML)")->required();
  cmd->add_option("-o,--out", args->out, "output file, FILE.gif")->required();
  cmd->add_option("--seconds", args->seconds, "simulated seconds shown (default 3)")
      ->check(CLI::Range(0.1, 60.0));
  cmd->add_option("--frames", args->frames, "frames in the GIF (default 60)")->check(CLI::Range(10, 200));
  cmd->add_option("--size", args->size, "image size in pixels, square (default 640)")->check(CLI::Range(200, 2000));
  cmd->add_option("--history", args->history, "a finished `millwear run` output folder of this design");
  cmd->add_option("--fidelity", args->fidelity, "draft | standard | reference (default: the scene's)");
  cmd->add_flag("--keep-data", args->keep_data, "keep the frame data next to the GIF (FILE_frames/)");
  cmd->callback([args, action] {
    *action = [args] {
      std::error_code ec;
      if (!fs::is_regular_file(args->scene, ec))
        throw InputError(args->scene, "", "a scene file (not found or not a regular file)");
      return run_animate(*args);
    };
  });
}

}  // namespace millwear::app
