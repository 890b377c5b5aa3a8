// A sweep of `millwear charge` over one scene key (see sweep.hpp).
#include "study/sweep.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <tuple>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <mutex>

#include "common/errors.hpp"
#include "common/parallel.hpp"
#include "common/text.hpp"
#include "common/units.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/folder_lock.hpp"
#include "io/run_folder.hpp"
#include "io/staging.hpp"
#include "metrics/batch_means.hpp"
#include "metrics/estimates.hpp"
#include "metrics/trajectories.hpp"
#include "plots/plots.hpp"
#include "scene/fidelity.hpp"
#include "study/charge_outputs.hpp"
#include "study/charge_run.hpp"
#include "wear/reshape.hpp"

#ifndef MILLWEAR_VERSION
#define MILLWEAR_VERSION "unknown"
#endif

namespace millwear::study {

namespace {

// 1000 values: a sweep is a curve, not a screen; more is a typo in the step.
constexpr std::size_t kMaxSweepValues = 1000;

bool parse_number(const std::string& text, double& v) {
  if (text.empty()) return false;
  char* end = nullptr;
  v = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size() && std::isfinite(v);
}

std::string value_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.12g", v);  // 0.7, not 0.69999999999999996
  return buf;
}

// The decimals of a number written plainly ("0.05": 2, "12": 0); -1 for one with an
// exponent ("5e-2") or too many to print.
int decimal_places(const std::string& text) {
  if (text.find_first_of("eExX") != std::string::npos) return -1;
  const std::size_t dot = text.find('.');
  const int places = dot == std::string::npos ? 0 : static_cast<int>(text.size() - dot - 1);
  return places <= 30 ? places : -1;
}

std::string fixed_text(double v, int places) {
  char buf[400];  // %.30f of a value up to 1e308
  std::snprintf(buf, sizeof buf, "%.*f", places, v);
  return buf;
}

// Replicate 1 (k = 0) in points/NN, replicate K in points/NN.rK.
std::string point_dir(const std::string& out, int index, int k = 0) {
  char buf[32];
  if (k == 0) std::snprintf(buf, sizeof buf, "%02d", index);
  else std::snprintf(buf, sizeof buf, "%02d.r%d", index, k + 1);
  return io::join_path(io::join_path(out, "points"), buf);
}

// Every file a sweep of these points writes into OUT, relative to it: its table, manifest and
// figures, and each point's charge files in its folder.
std::vector<std::string> sweep_output_names(const std::vector<Scene>& scenes, int reps) {
  std::vector<std::string> names = {"manifest.json", "sweep.csv", "plots/gnuplot.log"};
  for (const char* figure : {"power", "toe_shoulder", "collision_shear"})
    for (const char* ext : {".png", ".svg"}) names.push_back(std::string("plots/sweep_") + figure + ext);
  for (std::size_t i = 0; i < scenes.size(); ++i)
    for (int k = 0; k < reps; ++k) {
      const std::string dir = point_dir("", static_cast<int>(i), k);  // points/NN
      for (const std::string& f : charge_output_names(scenes[i])) names.push_back(dir + "/" + f);
    }
  return names;
}

// One point: `millwear charge` of its scene, its figures per mill with batch-means errors.
// One point's replicate K, run and written into its folder; `written` gets the files.
SweepPoint measure_point(const Scene& scene, int index, int k, const SweepAxis& axis, const std::string& out,
                         std::vector<std::string>& written) {
  SweepPoint p;
  p.index = index;
  p.text = axis.texts[static_cast<std::size_t>(index)];
  p.value = axis.values[static_cast<std::size_t>(index)];
  p.speed_fraction_critical = scene.mill.speed_fraction_critical;
  p.speed_rpm = rpm_from_rad_s(scene.angular_speed_rad_s());
  p.filling = scene.charge.filling;
  const auto t0 = std::chrono::steady_clock::now();
  const ChargeRunResult r = run_charge_only(scene);
  p.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  p.disks = r.disks;
  p.lost_disks = r.lost_disks;
  p.simulated_s = r.figures.summary.time_s;
  if (r.lost_disks > 0)
    p.error = std::to_string(r.lost_disks) + " of " + std::to_string(r.disks) + " disks lost (first: " +
              (r.events.empty() ? std::string("?") : r.events.front().what) + ")";

  // Per metre -> per mill: times the mill length. Per slice -> per metre: over the slice.
  const double L = scene.mill.length_m;
  const double t = scene.slice_thickness();
  const auto charge_t = [&](const ChargeFigures& f) { return f.summary.mass_kg / t * L * 1e-3; };
  const auto shear_kW = [&](const ChargeFigures& f) { return f.summary.shear_work_rate_W / t * 1e-3 * L; };
  const auto specific = [&](const ChargeFigures& f) {
    const double m = charge_t(f);
    return m > 0.0 ? f.power_kW_per_m * L / m : 0.0;
  };
  const ChargeFigures& f = r.figures;
  p.unsound = unsound_energy_split(f);
  p.unsteady = unsteady_window(f.summary);
  p.charge_t = charge_t(f);
  p.power_kW = f.power_kW_per_m * L;
  p.specific_kW_per_t = specific(f);
  p.collision_kW = f.collision_kW_per_m * L;
  p.shear_kW = shear_kW(f);
  p.toe_deg = f.summary.toe_deg;
  p.shoulder_deg = f.summary.shoulder_deg;
  p.centrifuged = f.summary.centrifuged;
  const auto sem = [&](auto of) {
    std::vector<double> v;
    for (const ChargeFigures& b : r.batches) v.push_back(of(b));
    return batch_means(v).sem;
  };
  p.power_kW_sem = sem([&](const ChargeFigures& b) { return b.power_kW_per_m * L; });
  p.specific_kW_per_t_sem = sem(specific);
  p.collision_kW_sem = sem([&](const ChargeFigures& b) { return b.collision_kW_per_m * L; });
  p.shear_kW_sem = sem(shear_kW);
  p.toe_deg_sem = sem([](const ChargeFigures& b) { return b.summary.toe_deg; });
  p.shoulder_deg_sem = sem([](const ChargeFigures& b) { return b.summary.shoulder_deg; });
  const ChargeEstimates est = charge_estimates(scene, r);
  p.liner_impact_share = est.impacts.window.liner_share;
  p.liner_impact_share_sem = est.impacts.liner_share.sem;

  const std::string dir = point_dir(out, index, k);
  io::ensure_dir(dir);
  written = write_charge_outputs(dir, scene, r, est, p.wall_s);
  return p;
}

void write_sweep_csv(const std::string& out, const SweepResult& r) {
  io::CsvTable t({"key", "value", "speed_fraction_critical", "speed_rpm", "filling", "disks", "charge_t",
                  "power_kW", "power_kW_sem", "specific_power_kW_per_t", "specific_power_kW_per_t_sem",
                  "collision_power_kW", "collision_power_kW_sem", "liner_shear_power_kW",
                  "liner_shear_power_kW_sem", "toe_deg", "toe_deg_sem", "shoulder_deg", "shoulder_deg_sem",
                  "centrifuged", "liner_impact_share", "liner_impact_share_sem", "replicates", "error_source",
                  "simulated_s", "wall_s", "lost_disks", "error"});
  // A centrifuged charge has no toe or shoulder: the cells say so (a plot skips them).
  const auto angle = [](const SweepPoint& p, double v) { return p.centrifuged ? io::CsvCell("centrifuged") : io::CsvCell(v); };
  const auto angle_sem = [](const SweepPoint& p, double v) { return p.centrifuged ? io::CsvCell("") : io::CsvCell(v); };
  // The share has no toe to go by when centrifuged, and no flight to go by when none landed.
  const auto share = [&](const SweepPoint& p) {
    return std::isfinite(p.liner_impact_share) ? io::CsvCell(p.liner_impact_share)
                                               : io::CsvCell(p.centrifuged ? "centrifuged" : "none");
  };
  const auto share_sem = [](const SweepPoint& p) {
    return std::isfinite(p.liner_impact_share) ? io::CsvCell(p.liner_impact_share_sem) : io::CsvCell("");
  };
  // The value as the scene took it where a double does not hold it (whole numbers past 2^53,
  // seeds): its shortest double would name another value, or the same for two points.
  const auto value = [](const SweepPoint& p) {
    return std::strtold(p.text.c_str(), nullptr) == static_cast<long double>(p.value) ? io::format_shortest(p.value)
                                                                                      : p.text;
  };
  for (const SweepPoint& p : r.points)
    t.add_row({r.axis.key, value(p), p.speed_fraction_critical, p.speed_rpm, p.filling, p.disks, p.charge_t,
               p.power_kW, p.power_kW_sem, p.specific_kW_per_t, p.specific_kW_per_t_sem, p.collision_kW,
               p.collision_kW_sem, p.shear_kW, p.shear_kW_sem, angle(p, p.toe_deg), angle_sem(p, p.toe_deg_sem),
               angle(p, p.shoulder_deg), angle_sem(p, p.shoulder_deg_sem), p.centrifuged, share(p), share_sem(p),
               p.replicates,
               std::string(error_source_name(p.replicates > 1 ? ErrorSource::Replicates : ErrorSource::BatchMeans)),
               p.simulated_s, p.wall_s, p.lost_disks, p.error});
  t.write(io::join_path(out, "sweep.csv"));
}

// Written once every point has ended, into the staging folder `out` with the sweep's other
// files (run_sweep).
void write_sweep_manifest(const std::string& out, const SweepRequest& q, const SweepResult& r,
                          const Scene& first, const std::vector<std::string>& files) {
  nlohmann::ordered_json m;
  m["program"] = "millwear";
  m["version"] = MILLWEAR_VERSION;
  m["commit"] = q.commit;
  m["command"] = "sweep";
  m["scene_file"] = q.scene_file;
  m["scene"] = r.scene_name;
  m["key"] = r.axis.key;
  m["values"] = r.axis.texts;
  m["set"] = q.overrides;
  m["fidelity"] = first.fidelity;
  m["revolutions"] = first.run.revolutions;
  m["seed"] = static_cast<unsigned long long>(first.solver.seed);
  m["replicates"] = q.replicates;
  m["error_source"] = error_source_name(q.replicates > 1 ? ErrorSource::Replicates : ErrorSource::BatchMeans);
  m["jobs"] = r.jobs;
  m["wall_s"] = r.wall_s;
  m["finished"] = true;  // every point ended: a stopped sweep writes no manifest into OUT
  nlohmann::ordered_json points = nlohmann::ordered_json::array();
  for (const SweepPoint& p : r.points) {
    nlohmann::ordered_json j;
    j["value"] = p.text;
    j["folder"] = io::relative_to(out, point_dir(out, p.index));
    j["status"] = p.error.empty() ? "finished" : "failed";
    if (!p.error.empty()) j["error"] = p.error;
    j["wall_s"] = p.wall_s;
    points.push_back(j);
  }
  m["points"] = points;
  if (!r.figure_error.empty()) m["figure_error"] = r.figure_error;
  m["files"] = files;
  io::write_file_atomic(io::join_path(out, "manifest.json"),
                        m.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) + "\n");
}

std::vector<std::string> render_sweep_figures(const std::string& out, const std::string& key) {
  std::vector<std::string> files;
  const std::string plots = io::plots_out_dir(out);
  io::ensure_dir(plots);
  std::string failures;
  for (const char* figure : {"power", "toe_shoulder", "collision_shear"}) {
    try {
      const std::string base = io::join_path(plots, std::string("sweep_") + figure);
      for (const auto& f : plots::render_figure(plots::script_path("sweep"),
                                                {{"datadir", out}, {"outbase", base}, {"figure", figure}, {"key", key}}))
        files.push_back(f);
    } catch (const RunError& e) {
      failures += (failures.empty() ? "" : "; ") + std::string(e.what());
    }
  }
  if (!failures.empty()) throw RunError(failures);
  return files;
}

}  // namespace

SweepPoint fold_replicates(const std::vector<SweepPoint>& reps) {
  SweepPoint p = reps.front();
  p.replicates = static_cast<int>(reps.size());
  if (reps.size() < 2) return p;
  const auto fold = [&reps](double SweepPoint::*value, double SweepPoint::*sem) {
    std::vector<double> x;
    for (const SweepPoint& r : reps) x.push_back(r.*value);
    const Estimate e = mean_and_se(x);
    return std::make_pair(e.mean, e.se);
  };
  const std::pair<double SweepPoint::*, double SweepPoint::*> figures[] = {
      {&SweepPoint::power_kW, &SweepPoint::power_kW_sem},
      {&SweepPoint::specific_kW_per_t, &SweepPoint::specific_kW_per_t_sem},
      {&SweepPoint::collision_kW, &SweepPoint::collision_kW_sem},
      {&SweepPoint::shear_kW, &SweepPoint::shear_kW_sem},
      {&SweepPoint::toe_deg, &SweepPoint::toe_deg_sem},
      {&SweepPoint::shoulder_deg, &SweepPoint::shoulder_deg_sem},
      {&SweepPoint::liner_impact_share, &SweepPoint::liner_impact_share_sem}};
  for (const auto& [value, sem] : figures) std::tie(p.*value, p.*sem) = fold(value, sem);
  p.charge_t = 0.0;
  p.simulated_s = p.wall_s = 0.0;
  p.lost_disks = 0;
  p.centrifuged = false;
  for (const SweepPoint& r : reps) {
    p.charge_t += r.charge_t / static_cast<double>(reps.size());
    p.simulated_s += r.simulated_s;
    p.wall_s += r.wall_s;
    p.lost_disks += r.lost_disks;
    p.centrifuged = p.centrifuged || r.centrifuged;
    if (p.error.empty() && !r.error.empty()) p.error = r.error;
    if (p.unsound.empty() && !r.unsound.empty()) p.unsound = r.unsound;
    if (p.unsteady.empty() && !r.unsteady.empty()) p.unsteady = r.unsteady;
  }
  return p;
}

bool SweepResult::failed() const {
  return std::any_of(points.begin(), points.end(), [](const SweepPoint& p) { return !p.error.empty(); });
}

namespace {

// FIRST:LAST:STEP written as whole numbers ("+-" and digits only).
bool all_whole_numbers(const std::vector<std::string>& parts) {
  return std::all_of(parts.begin(), parts.end(), [](const std::string& t) {
    return !t.empty() && t.find_first_not_of("+-0123456789") == std::string::npos;
  });
}

// A range of whole numbers (seeds run to 2^63 - 1, past the 2^53 a double counts exactly)
// stepped in extended precision, exact to 2^64, and written as the integers they are.
SweepAxis whole_number_range(SweepAxis a, const std::vector<std::string>& parts, const std::string& rest) {
  const long double first = std::strtold(parts[0].c_str(), nullptr), last = std::strtold(parts[1].c_str(), nullptr),
                    step = std::strtold(parts[2].c_str(), nullptr);
  const auto text = [](long double v) {
    char buf[48];
    std::snprintf(buf, sizeof buf, "%.0Lf", v);
    return std::string(buf);
  };
  if (last < first) throw InputError("", "--vary " + a.key, "expected LAST >= FIRST, got " + rest);
  const long double n = std::floor((last - first) / step);
  if (first + n * step != last)
    throw InputError("", "--vary " + a.key,
                     "expected LAST reached from FIRST in whole steps, got " + rest + ": the values go " +
                         text(first + n * step) + ", then " + text(first + (n + 1) * step));
  if (n + 1 > static_cast<long double>(kMaxSweepValues))
    throw InputError("", "--vary " + a.key, "expected at most " + std::to_string(kMaxSweepValues) + " values, got " +
                                                text(n + 1));
  for (long double i = 0; i <= n; ++i) {
    a.texts.push_back(text(first + i * step));
    a.values.push_back(std::stod(a.texts.back()));
  }
  return a;
}

}  // namespace

SweepAxis parse_vary(const std::string& text) {
  const std::string usage = "KEY=FIRST:LAST:STEP or KEY=V1,V2,... with numbers, e.g. --vary mill.speed=0.5:1.0:0.05";
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) throw InputError("", "--vary", "expected " + usage);
  SweepAxis a;
  a.key = trim(text.substr(0, eq));
  const std::string rest = text.substr(eq + 1);
  if (a.key.empty() || a.key.find_first_of(" \t") != std::string::npos) throw InputError("", "--vary", "expected " + usage);
  // A sweep runs the charge alone (`millwear charge` per point): no key of [wear] changes it,
  // and a sweep over one would give the same point at every value.
  if (a.key.rfind("wear.", 0) == 0)
    throw InputError("", "--vary " + a.key,
                     "a key the charge reads (mill, lifters, charge, solver): a sweep runs the charge alone, without "
                     "wear, so every value of " + a.key + " gives the same point; `millwear run` or `tradeoff` "
                     "measure the wear settings");
  // Nor do the keys of a wear history outside [wear] (a liner's hours, the hours between
  // reversals: the charge turns one way) or what is written (ParaView frames take the same steps).
  if (a.key.rfind("outputs.", 0) == 0 || a.key == "lifters.start_hours" || a.key == "mill.reverse_every")
    throw InputError("", "--vary " + a.key,
                     "a key the charge reads (mill, lifters, charge, solver): " + a.key +
                         (a.key.rfind("outputs.", 0) == 0 ? " says what is written, not what is measured"
                                                          : " counts the hours of a wear history, which the charge has not") +
                         ", so every value gives the same point");
  if (rest.find(':') != std::string::npos) {
    std::vector<std::string> parts;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= rest.size(); ++i)
      if (i == rest.size() || rest[i] == ':') parts.push_back(trim(rest.substr(start, i - start))), start = i + 1;
    double first = 0, last = 0, step = 0;
    if (parts.size() != 3 || !parse_number(parts[0], first) || !parse_number(parts[1], last) ||
        !parse_number(parts[2], step))
      throw InputError("", "--vary " + a.key, "expected FIRST:LAST:STEP, three numbers, got '" + rest + "'");
    if (!(step > 0.0)) throw InputError("", "--vary " + a.key, "expected a STEP > 0, got " + parts[2]);
    if (all_whole_numbers(parts)) return whole_number_range(std::move(a), parts, rest);
    if (last < first) throw InputError("", "--vary " + a.key, "expected LAST >= FIRST, got " + rest);
    // A millionth of a step: 0.5:1.6:0.1 ends at 1.6, whatever the rounding of 11 x 0.1.
    const double n = std::floor((last - first) / step + 1e-6);
    // LAST is one of the values: a range whose steps pass it would leave it out unsaid.
    if (std::abs(first + n * step - last) > 1e-6 * step)
      throw InputError("", "--vary " + a.key,
                       "expected LAST reached from FIRST in whole steps, got " + rest + ": the values go " +
                           value_text(first + n * step) + ", then " + value_text(first + (n + 1) * step));
    if (n + 1 > static_cast<double>(kMaxSweepValues))
      throw InputError("", "--vary " + a.key, "expected at most " + std::to_string(kMaxSweepValues) + " values, got " +
                                                  value_text(n + 1));
    // FIRST + i STEP carries the rounding of binary fractions (0.5 + 2 x 0.1 is
    // 0.7000000000000001): written FIRST and STEP in plain decimals, every value has no more
    // decimals than they have, and is rounded to those; else to 12 significant digits. Twelve
    // digits alone would round a seed of 13 digits to 1e+12, or a FIRST typed to 13 digits.
    const int places = std::max(decimal_places(parts[0]), decimal_places(parts[2]));
    for (int i = 0; i <= static_cast<int>(n); ++i) {
      const double raw = first + i * step;
      const double v = std::stod(places >= 0 && decimal_places(parts[1]) >= 0 ? fixed_text(raw, places) : value_text(raw));
      a.values.push_back(v);
      a.texts.push_back(io::format_shortest(v));
    }
  } else {
    // The values as the scene reads them are compared and ordered in extended precision:
    // seeds are integers up to 2^63 - 1, which a double tells apart only up to 2^53.
    std::vector<long double> exact;
    std::size_t start = 0;
    for (std::size_t i = 0; i <= rest.size(); ++i) {
      if (i != rest.size() && rest[i] != ',') continue;
      const std::string item = trim(rest.substr(start, i - start));
      start = i + 1;
      double v = 0;
      if (!parse_number(item, v))
        throw InputError("", "--vary " + a.key, "expected a number, got '" + item + "' (" + usage + ")");
      const long double x = std::strtold(item.c_str(), nullptr);
      // A value twice would run the same charge twice (same scene, same seed): the same in
      // extended precision, or, for a value with a fraction (which a key reads as a double),
      // the same double (0.6 and 0.60000000000000001).
      const bool whole = x == std::floor(x);
      for (std::size_t k = 0; k < exact.size(); ++k)
        if (exact[k] == x || (!(whole && exact[k] == std::floor(exact[k])) && a.values[k] == v))
          throw InputError("", "--vary " + a.key,
                           "expected each value once, got " + a.texts[k] + " and " + item + " (--replicates N runs more "
                           "seeds of a value)");
      a.values.push_back(v);
      a.texts.push_back(item);
      exact.push_back(x);
    }
    if (a.values.size() > kMaxSweepValues)
      throw InputError("", "--vary " + a.key, "expected at most " + std::to_string(kMaxSweepValues) + " values");
    // A sweep is a curve: its points in ascending order, as its table lists them and its
    // figures join them (0.8,0.5,0.65 drawn in the order typed would double back on itself).
    std::vector<std::size_t> order(a.values.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::stable_sort(order.begin(), order.end(), [&exact](std::size_t i, std::size_t j) { return exact[i] < exact[j]; });
    SweepAxis sorted{a.key, {}, {}};
    for (std::size_t k : order) {
      sorted.values.push_back(a.values[k]);
      sorted.texts.push_back(a.texts[k]);
    }
    a = std::move(sorted);
  }
  return a;
}

namespace {

// A scene's message without the point's value among the overrides it lists ("(the scene with
// --set A --set KEY=VALUE)", load_scene): the point is named as its --vary.
std::string without_vary_set(std::string expected, const std::string& vary) {
  const std::string last = " --set " + vary + ")";
  if (expected.size() < last.size() || expected.compare(expected.size() - last.size(), last.size(), last) != 0)
    return expected;
  expected.erase(expected.size() - last.size());
  expected += ")";
  const std::string none = " (the scene with)";
  if (expected.size() >= none.size() && expected.compare(expected.size() - none.size(), none.size(), none) == 0)
    expected.erase(expected.size() - none.size());
  return expected;
}

// A key this sweep's charge does not read gives the same point at every value: the other
// backend's solver settings, and the window's revolutions --revolutions sets for every point.
void check_key_is_read(const SweepRequest& q, const std::string& key, const Scene& scene) {
  const bool box2d = scene.solver.backend == Backend::Box2D;
  const char* backend = box2d ? "box2d" : "soft";
  const std::vector<std::string> other_backend =
      box2d ? std::vector<std::string>{"solver.substeps", "solver.contact_hertz", "solver.damping_ratio", "solver.push_out"}
            : std::vector<std::string>{"solver.velocity_iterations", "solver.position_iterations"};
  std::string why;
  if (std::find(other_backend.begin(), other_backend.end(), key) != other_backend.end())
    why = "the scene's backend (" + std::string(backend) + ") does not read " + key;
  else if (key == "run.revolutions" && q.revolutions > 0.0)
    why = "--revolutions " + io::format_number(q.revolutions) + " sets every point's revolutions";
  if (!why.empty())
    throw InputError(q.scene_file, "--vary " + key,
                     "a key the sweep's charge reads: " + why + ", so every value gives the same point");
}

// Replicate K of a point runs its scene with seed + K - 1: a sweep of the seed itself with
// replicates would run one charge in two points unless its seeds are that far apart.
void check_seeds_apart(const SweepRequest& q, const SweepAxis& axis, const std::vector<Scene>& scenes) {
  const auto reps = static_cast<std::uint64_t>(std::max(1, q.replicates));
  if (axis.key != "solver.seed" || reps < 2) return;
  for (std::size_t i = 1; i < scenes.size(); ++i)  // the values ascend (parse_vary)
    if (scenes[i].solver.seed - scenes[i - 1].solver.seed < reps)
      throw InputError("", "--vary solver.seed",
                       "seeds at least --replicates (" + std::to_string(reps) + ") apart, as each point's replicates "
                       "run seeds s .. s + " + std::to_string(reps - 1) + "; got " + axis.texts[i - 1] + " and " +
                           axis.texts[i] + ", which would run the same charges");
}

}  // namespace

std::vector<Scene> sweep_scenes(const SweepRequest& q, const SweepAxis& axis) {
  if (!q.fidelity.empty()) fidelity_preset(q.fidelity);  // InputError for a bad name
  // The varied value goes in after the --set overrides: one it replaces would be dropped at
  // every point.
  for (const std::string& set : q.overrides)
    if (!axis.texts.empty() && override_replaces(axis.key + "=" + axis.texts.front(), set))
      throw InputError("", "--set " + printable(set, 80),
                       "a key --vary " + axis.key + " leaves in place: the varied value replaces it at every point");
  std::vector<Scene> scenes;
  for (const std::string& text : axis.texts) {
    std::vector<std::string> overrides = q.overrides;
    const std::string vary = axis.key + "=" + text;
    overrides.push_back(vary);
    Scene s;
    try {
      s = load_scene(q.scene_file, overrides);
    } catch (const InputError& e) {
      // The varied value's problem is the --vary's: say so. A --set's own is its; another
      // key's at this point (a limit the value moved) names the point.
      const std::string set = "--set " + vary;
      if (e.where.compare(0, set.size(), set) == 0)
        throw InputError(e.file, "--vary " + vary + e.where.substr(set.size()), e.expected);
      if (e.where.compare(0, 6, "--set ") == 0) throw;
      throw InputError(e.file, e.where + " (at --vary " + vary + ")", without_vary_set(e.expected, vary));
    }
    // The point's charge_summary.csv records its value with the --set overrides, as `charge
    // --set` would: a point's folder says which point it is.
    if (!q.fidelity.empty()) apply_fidelity(s, q.fidelity);
    if (q.revolutions > 0.0) s.run.revolutions = q.revolutions;
    try {
      check_scene(s, q.scene_file);
    } catch (const InputError& e) {
      // A limit this point's value breaks: name the point too.
      throw InputError(e.file, e.where + " (at --vary " + vary + ")", e.expected);
    }
    scenes.push_back(std::move(s));
  }
  check_key_is_read(q, axis.key, scenes.front());
  check_seeds_apart(q, axis, scenes);
  return scenes;
}

SweepResult run_sweep(const SweepRequest& q, const SweepCallbacks& cb) {
  const auto t0 = std::chrono::steady_clock::now();
  SweepResult r;
  r.axis = parse_vary(q.vary);
  const std::vector<Scene> scenes = sweep_scenes(q, r.axis);  // every point checked; nothing written
  for (const Scene& s : scenes)  // a sweep may vary solver.seed itself
    check_derived_seeds(s, static_cast<std::uint64_t>(std::max(1, q.replicates)),
                        "--replicates " + std::to_string(q.replicates));
  r.scene_name = scenes.front().name;
  const int n = static_cast<int>(scenes.size());
  const int reps = std::max(1, q.replicates);
  const int tasks = n * reps;
  r.jobs = jobs_for(q.jobs, static_cast<std::size_t>(tasks));
  const io::FolderLock lock(q.out, "sweep");  // one writer per folder, for the whole sweep
  io::check_output_names(q.out, sweep_output_names(scenes, reps), "sweep");  // before any work
  // The points and figures are drawn up beside an earlier sweep's, which stay in OUT as they
  // were until the sweep has ended (a sweep stopped part-way, or one that fails, leaves them);
  // then the earlier sweep's files that no new one replaces go (a point it no longer has).
  io::StagedOutputs staged(q.out);
  const std::string& out = staged.dir();
  if (cb.on_start) cb.on_start(r.axis, r.jobs);

  // Threads take the next (point, replicate); each is independent (its own engine, its own
  // seed: replicate K of a point runs the point's scene with seed + K - 1).
  std::vector<std::vector<SweepPoint>> measured(static_cast<std::size_t>(n), std::vector<SweepPoint>(static_cast<std::size_t>(reps)));
  std::vector<int> left(static_cast<std::size_t>(n), reps);
  std::vector<std::vector<std::string>> written(static_cast<std::size_t>(tasks));  // per task
  r.points.resize(static_cast<std::size_t>(n));
  std::mutex mutex;
  int done = 0;
  // A numerical failure, or a charge the fill cannot place at this point's value (the up-front
  // check cannot see it), is the point's result; anything else (an I/O failure) stops the sweep.
  for_each_index_parallel(static_cast<std::size_t>(tasks), r.jobs, [&](std::size_t t) {
    const int i = static_cast<int>(t) / reps, k = static_cast<int>(t) % reps;
    const auto iu = static_cast<std::size_t>(i);
    SweepPoint p;
    try {
      Scene scene = scenes[iu];
      scene.solver.seed += static_cast<std::uint64_t>(k);
      p = measure_point(scene, i, k, r.axis, out, written[t]);
    } catch (const NumericalError& e) {
      p.index = i, p.text = r.axis.texts[iu], p.value = r.axis.values[iu];
      p.error = e.what();
    } catch (const InputError& e) {
      if (e.where != "charge.filling") throw;
      p.index = i, p.text = r.axis.texts[iu], p.value = r.axis.values[iu];
      p.error = e.what();
    }
    std::lock_guard<std::mutex> g(mutex);
    measured[iu][static_cast<std::size_t>(k)] = p;
    if (--left[iu] == 0) {
      r.points[iu] = fold_replicates(measured[iu]);
      ++done;
      if (cb.on_point) cb.on_point(r.points[iu], done, n);
    }
  });

  write_sweep_csv(out, r);
  // The files in task order (the order they ended in depends on the threads).
  std::vector<std::string> files = {"manifest.json", "sweep.csv"};
  for (const std::vector<std::string>& task_files : written) {
    std::vector<std::string> in_point;
    for (const std::string& f : task_files) in_point.push_back(io::relative_to(out, f));
    std::sort(in_point.begin(), in_point.end());
    files.insert(files.end(), in_point.begin(), in_point.end());
  }
  if (q.figures) {
    try {
      r.figure_files = render_sweep_figures(out, r.axis.key);
    } catch (const std::exception& e) {
      r.figure_error = staged.in_out_text(e.what());
      r.figures_failed = plots::gnuplot_available();
    }
    for (const auto& f : r.figure_files) files.push_back(io::relative_to(out, f));
    // gnuplot's messages, listed so that a sweep without figures into the folder removes them.
    std::error_code ec;
    if (std::filesystem::is_regular_file(io::join_path(io::plots_out_dir(out), "gnuplot.log"), ec))
      files.push_back("plots/gnuplot.log");
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  write_sweep_manifest(out, q, r, scenes.front(), files);
  staged.commit({q.scene_file});
  for (std::string& f : r.figure_files) f = staged.in_out(f);
  return r;
}

}  // namespace millwear::study
