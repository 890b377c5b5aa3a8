// The charge tumbling as an animated GIF (see animation.hpp): the liners to show, the
// simulation that records the frames, the colour scale, the frame files, gnuplot.
#include "study/animation.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <vector>

#include "common/errors.hpp"
#include "common/units.hpp"
#include "engine/engine.hpp"
#include "io/atomic_write.hpp"
#include "io/run_folder.hpp"
#include "plots/plots.hpp"
#include "scene/fidelity.hpp"
#include "scene/scene.hpp"
#include "study/plan.hpp"
#include "study/run_outputs.hpp"
#include "study/stage_files.hpp"
#include "wear/reshape.hpp"
#include "wear/window.hpp"

namespace millwear::study {

namespace fs = std::filesystem;

namespace {

// Thrown by the stop check: the animation ends where it is, nothing drawn.
struct Stopped {};

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

// The finished stages' liners of a run folder, coloured by their wear rates.
std::vector<Segment> history_segments(const Scene& scene, const std::string& history) {
  const int last = io::last_finished_stage(history, scene.name);
  if (last < 0)
    throw InputError(history, "--history",
                     "a `millwear run` output folder with finished stages of design '" + scene.name + "' (no " +
                         scene.name + "_stage0.done in " + io::stages_dir(history) + ")");
  // The run's liners are drawn under the scene's name and charge: the run must be the scene's.
  study::check_run_of_scene(history, scene, "--history");
  std::vector<Segment> segments;
  for (int k = 0; k <= last; ++k) {
    StageRecord rec = study::read_stage_state(history, scene.name, k);
    study::check_stage_of_scene(rec, scene, history, "--history");
    if (rec.units.empty() || rec.edge_wear_rate_m_per_s.empty()) continue;  // worn-out marker
    Segment s;
    s.mill = build_mill(scene.radius_m(), scene.mill.rows, rec.units, scene.mill.kind_count());
    if (rec.edge_wear_rate_m_per_s.size() != s.mill.boundary.size())
      throw InputError(io::stages_dir(history), scene.name + "_stage" + std::to_string(k) + ".edges.csv",
                       "one wear rate per liner edge, " + std::to_string(s.mill.boundary.size()) + ", found " +
                           std::to_string(rec.edge_wear_rate_m_per_s.size()));
    s.edge_value = rec.edge_wear_rate_m_per_s;
    for (double& v : s.edge_value) v = mm_per_1000h(v);
    s.stage = k;
    s.hours = rec.hours;
    segments.push_back(std::move(s));
  }
  if (segments.empty()) throw InputError(history, "--history", "stages with a liner and wear rates");
  return segments;
}

// Settle, spin up, then record frames evenly over the animated seconds, switching to each
// segment's liner in turn. Without a history the one segment gets the window's shear work
// rate per unit liner area as its colour.
std::vector<Frame> simulate_frames(const Scene& scene, std::vector<Segment>& segments, const AnimationRequest& a,
                                   std::size_t& disks, double& seconds, const std::function<void()>& check_stop) {
  const ChargeState initial = fill_charge(scene, segments.front().mill);
  disks = initial.size();
  auto engine = make_engine(scene, segments.front().mill, initial, accounting_options_for(scene));
  double dir = direction_at(scene, segments.front().hours);
  settle_and_spin_up(*engine, scene, dir, check_stop);
  engine->reset_window();
  const double start_s = engine->state().time_s;
  const int nframes = a.frames;
  const int steps_per_frame = std::max(1, steps_for(a.seconds / nframes, engine->time_step_s()));
  seconds = nframes * steps_per_frame * engine->time_step_s();
  std::vector<Frame> frames;
  frames.reserve(static_cast<std::size_t>(nframes));
  std::size_t seg = 0;
  for (int f = 0; f < nframes; ++f) {
    const std::size_t want = std::min(segments.size() - 1,
                                      static_cast<std::size_t>(f) * segments.size() / static_cast<std::size_t>(nframes));
    if (want != seg) {
      seg = want;
      engine->set_liner(segments[seg].mill);
      const double d = direction_at(scene, segments[seg].hours);
      if (d != dir) {
        // A reversal: the charge falls back and is lifted the other way. Let it settle into
        // its new shape (the scene's spin-up) before the next frame is drawn.
        dir = d;
        engine->set_mill_speed(dir * scene.angular_speed_rad_s());
        step_checking_stop(*engine,
                           steps_for(scene.solver.spinup_revolutions * scene.revolution_time_s(), engine->time_step_s()),
                           check_stop);
      }
    }
    step_checking_stop(*engine, steps_per_frame, check_stop);
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
  if (a.history.empty()) {
    const Accounting& acc = engine->accounting();
    Segment& s = segments.front();
    s.edge_value.assign(s.mill.boundary.size(), 0.0);
    const double t = scene.slice_thickness();
    for (std::size_t e = 0; e < s.edge_value.size() && e < acc.shear_work_J.size(); ++e)
      s.edge_value[e] = acc.time_s > 0 ? acc.shear_work_J[e] / acc.time_s / (s.mill.edge_length_m[e] * t) : 0.0;
  }
  return frames;
}

// Colour scale to the 98th percentile: a few hot edges (a lifter's leading corner) would
// otherwise leave the rest of the liner one colour. Hotter edges show at the top colour.
double colour_scale_max(const std::vector<Segment>& segments) {
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
  return cbmax;
}

// The data file (per frame: disks "x y r species", then the liner path "x y value") and the
// meta file (frame count, radius, colour scale, titles) that plots/animate.gp reads.
// --keep-data writes its frames into FILE_frames/: a folder that is not one an earlier
// animation left (only its frames.dat, frames_meta.gp and gnuplot.log, the meta file in its
// own format) is the user's, refused before anything is simulated.
void check_frames_folder(const std::string& folder) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(folder, ec))) return;
  if (!fs::is_directory(folder, ec))
    throw InputError("", "--keep-data", "the frames' folder " + folder + " to be free, found a file of that name");
  for (const auto& e : fs::directory_iterator(folder, ec)) {
    const std::string name = e.path().filename().string();
    if (name != "frames.dat" && name != "frames_meta.gp" && name != "gnuplot.log")
      throw InputError("", "--keep-data", "the frames' folder " + folder + " to hold an earlier animation's files "
                       "only; it holds " + name + " (move it, or give -o another name)");
  }
  std::ifstream meta(folder + "/frames_meta.gp");
  std::string first;
  if (!fs::is_empty(folder, ec) && !(meta && std::getline(meta, first) && first.rfind("nframes = ", 0) == 0))
    throw InputError("", "--keep-data", "the frames' folder " + folder + " to hold an earlier animation's files "
                     "only; its frames_meta.gp is missing or not one this command wrote (move the folder, or "
                     "give -o another name)");
}

void write_frame_files(const Scene& scene, const std::vector<Segment>& segments, const std::vector<Frame>& frames,
                       const std::string& cblabel, bool history, const std::string& datafile,
                       const std::string& metafile) {
  std::string data;
  data.reserve(frames.size() * 8000);
  std::ostringstream meta;
  meta << "nframes = " << frames.size() << "\nR = " << fmt(scene.radius_m(), "%.17g")
       << "\ncbmax = " << fmt(colour_scale_max(segments), "%.17g") << "\ncblabel = " << gp_string(cblabel)
       << "\narray ftitle[" << frames.size() << "]\n";
  // The species as the figures name and colour them (plots::species_colours).
  const auto& species = scene.charge.species;
  std::vector<bool> balls;
  for (const auto& sp : species) balls.push_back(sp.is_ball);
  const std::vector<std::string> colours = plots::species_colours(balls);
  meta << "nspecies = " << species.size() << "\narray sp_rgb[" << species.size() << "]\narray sp_name["
       << species.size() << "]\n";
  for (std::size_t k = 0; k < species.size(); ++k)
    meta << "sp_rgb[" << k + 1 << "] = " << std::stol(colours[k].substr(1), nullptr, 16) << "\nsp_name[" << k + 1
         << "] = " << gp_string(species[k].name) << "\n";
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
      const Vec2 p = rotated(s.mill.boundary[e % n], fr.mill_angle);
      data += fmt(p.x) + " " + fmt(p.y) + " " + fmt(s.edge_value[e % n]) + "\n";
    }
    const double rpm = rpm_from_rad_s(std::fabs(fr.speed));
    std::string title = scene.name + "   t = " + fmt(fr.time_s, "%.2f") + " s   " + fmt(rpm, "%.1f") + " rpm " +
                        (fr.speed >= 0 ? "(counter-clockwise)" : "(clockwise)");
    if (history) title += "\\nliner after stage " + std::to_string(s.stage) + " (" + fmt(s.hours, "%.0f") + " h)";
    std::string quoted;
    for (char c : title) {
      if (c == '"') quoted += '\\';
      quoted += c;
    }
    meta << "ftitle[" << f + 1 << "] = " << "\"" << quoted << "\"\n";
  }
  io::write_file_atomic(datafile, data);
  io::write_file_atomic(metafile, meta.str());
}

}  // namespace

AnimationOutcome make_animation(const AnimationRequest& a) {
  std::error_code ec;
  if (!fs::is_regular_file(a.scene_file, ec))
    throw InputError(a.scene_file, "", "a scene file (not found or not a regular file)");
  Scene scene = study::load_checked_scene(a.scene_file, a.overrides, a.fidelity);
  if (a.out.size() < 5 || a.out.substr(a.out.size() - 4) != ".gif")
    throw InputError("", "-o", "an output file name ending in .gif, found '" + a.out + "'");
  // A frame is a whole number of time steps: frames shorter than one step would each be one,
  // and the animation would show more seconds than asked (0.1 s in 200 frames of 1 ms steps
  // showed 0.2 s).
  const double dt_s = scene.solver.time_step_s;
  if (a.seconds / a.frames < dt_s * (1.0 - 1e-9)) {
    char buf[320];
    std::snprintf(buf, sizeof buf,
                  "at most one frame per time step of the scene (%.6g s): %d frames of %.6g s need --seconds of "
                  "at least %.6g, or at most %d frames for %.6g s",
                  dt_s, a.frames, a.seconds, a.frames * dt_s, static_cast<int>(std::floor(a.seconds / dt_s * (1.0 + 1e-9))),
                  a.seconds);
    throw InputError("", "--frames", buf);
  }
  // The GIF replaces no file the animation reads (a scene or profile that happens to end in .gif).
  {
    const fs::path gif = fs::path(a.out);
    io::check_inputs_not_among(gif.parent_path().empty() ? "." : gif.parent_path().string(),
                               {gif.filename().string()}, study::scene_input_files(scene), "animate");
  }
  const std::string outbase = a.out.substr(0, a.out.size() - 4);
  if (a.keep_data) check_frames_folder(outbase + "_frames");
  // The GIF is all this command makes: without gnuplot, say so before simulating anything.
  if (!plots::gnuplot_available())
    throw RunError("gnuplot not found on PATH: the animation is drawn by gnuplot's gif terminal (for example "
                   "`apt-get install gnuplot-nox`); nothing was simulated or written");

  AnimationOutcome o;
  o.scene_name = scene.name;
  o.from_history = !a.history.empty();
  std::vector<Segment> segments;
  std::string cblabel;
  if (o.from_history) {
    segments = history_segments(scene, a.history);
    cblabel = "Liner wear rate (mm per 1000 h)";
    // A frame per finished stage at least: with fewer, stages (the last, most worn one among
    // them) would be skipped.
    if (static_cast<std::size_t>(a.frames) < segments.size())
      throw InputError("", "--frames",
                       "at least one frame per finished stage of " + a.history + " (" +
                           std::to_string(segments.size()) + " stages) with --history, got " +
                           std::to_string(a.frames));
  } else {
    Segment s;
    s.mill = build_scene_mill(scene);
    segments.push_back(std::move(s));
    cblabel = "Liner shear work rate (W/m^2)";
  }

  const auto t0 = std::chrono::steady_clock::now();
  const auto stop = [&a] { return a.stop_signal ? a.stop_signal->load() : 0; };
  std::vector<Frame> frames;
  try {
    frames = simulate_frames(scene, segments, a, o.disks, o.seconds, [&stop] {
      if (stop() != 0) throw Stopped{};
    });
  } catch (const Stopped&) {
    o.stopped_by = stop();  // nothing written yet
    return o;
  }
  o.frames = frames.size();
  o.last_stage = segments.back().stage;

  const fs::path work = a.keep_data ? fs::path(outbase + "_frames")
                                    : fs::temp_directory_path() / ("millwear-animate-" + std::to_string(::getpid()));
  // The GIF is drawn to a temporary name beside FILE and renamed over it once gnuplot has
  // ended and no stop came: a stop while gnuplot draws (Ctrl-C reaches it too) leaves no GIF
  // in part, and an earlier FILE as it was. The temporary folder goes on every way out but a
  // failure, whose message names its gnuplot.log.
  // (A short temporary name: FILE's own may be near the longest name a folder takes.)
  const std::string drawn_base = io::temp_path_for((fs::path(a.out).parent_path() / "animation").string());
  const std::string drawn = drawn_base + ".gif";
  const auto clean_up = [&] {
    fs::remove(drawn, ec);
    if (!a.keep_data) fs::remove_all(work, ec);
  };
  try {
    fs::create_directories(work);
    const std::string datafile = (work / "frames.dat").string(), metafile = (work / "frames_meta.gp").string();
    write_frame_files(scene, segments, frames, cblabel, o.from_history, datafile, metafile);
    const int delay = std::max(2, static_cast<int>(std::lround(100.0 * a.seconds / a.frames)));
    const fs::path parent = fs::path(a.out).parent_path();
    if (!parent.empty()) io::ensure_dir(parent.string());
    if (stop() == 0)
      plots::render_figure(plots::script_path("animate"),
                           {{"datafile", datafile}, {"metafile", metafile}, {"outbase", drawn_base},
                            {"formats", "gif"}, {"delay", std::to_string(delay)}, {"size", std::to_string(a.size)}},
                           (work / "gnuplot.log").string());
  } catch (...) {
    if (stop() != 0) {  // gnuplot stopped by the same Ctrl-C: a stop, not a failure
      clean_up();
      o.stopped_by = stop();
      if (a.keep_data && fs::exists(work / "frames_meta.gp", ec)) o.data_dir = work.string();
      return o;
    }
    // A failure: the frame data and gnuplot's log stay where the message points.
    fs::remove(drawn, ec);
    throw;
  }
  if (stop() != 0) {
    clean_up();
    o.stopped_by = stop();
    if (a.keep_data) o.data_dir = work.string();
    return o;
  }
  if (::rename(drawn.c_str(), a.out.c_str()) != 0) {
    const int err = errno;
    clean_up();
    throw RunError("cannot write " + a.out + ": rename from " + drawn + " failed (" + std::strerror(err) + ")");
  }
  if (!a.keep_data) fs::remove_all(work, ec);
  else o.data_dir = work.string();
  o.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return o;
}

}  // namespace millwear::study
