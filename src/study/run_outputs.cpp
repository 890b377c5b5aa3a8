// summary.csv, spectrum.csv and manifest.json from a run's report.
#include "study/run_outputs.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>

#include "common/errors.hpp"
#include "common/units.hpp"
#include "engine/accounting.hpp"
#include "engine/soft/model.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/hash.hpp"
#include "io/run_folder.hpp"
#include "metrics/charge_summary.hpp"
#include "scene/limits.hpp"
#include "wear/reshape.hpp"

namespace millwear::study {

namespace {

// Insertion order kept, so the manifest reads in the order it is written.
using Json = nlohmann::ordered_json;

// A number, or null where it is not finite (JSON has no NaN or infinity).
Json number(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }

const char* direction_name(Direction d) {
  switch (d) {
    case Direction::Forward: return "forward";
    case Direction::Reverse: return "reverse";
    case Direction::Bidirectional: return "bidirectional";
  }
  return "?";
}

// The lifter's points (and a measured surface's), every kind of a pattern: what a profile of
// the same name but other points changes.
std::string lifter_shape_hash(const Scene& s) {
  std::string bytes;
  const auto add = [&bytes](const Polyline& line) {
    for (const Vec2& p : line) bytes += io::format_exact(p.x) + "," + io::format_exact(p.y) + "\n";
    bytes += "--\n";
  };
  add(s.mill.lifter.points);
  add(s.mill.lifter.measured);
  for (const LifterProfile& p : s.mill.pattern) {
    add(p.points);
    add(p.measured);
  }
  return io::stable_hash_hex(bytes);
}

Json scene_settings(const Scene& s) {
  Json j;
  j["mill"] = Json{
      {"diameter_m", s.mill.diameter_m},
      {"length_m", s.mill.length_m},
      {"slice_thickness_m", s.slice_thickness()},
      {"speed_fraction_critical", s.mill.speed_fraction_critical},
      {"speed_rpm", rpm_from_rad_s(s.angular_speed_rad_s())},
      {"direction", direction_name(s.mill.direction)},
      {"reverse_every_hours", s.mill.reverse_every_hours},
      {"rows", s.mill.rows},
      {"lifter_profile", s.mill.lifter.name},
      {"lifter_shape", lifter_shape_hash(s)},
      {"lifter_pattern", [&s] {
         Json names = Json::array();
         for (const auto& p : s.mill.pattern) names.push_back(p.name);
         return names;
       }()},
      {"shell_edge_m", s.mill.mesh.shell_edge_m},
      {"lifter_edge_m", s.mill.mesh.lifter_edge_m}};
  j["charge"] = Json{
      {"filling", s.charge.filling},
      {"ball_filling", s.charge.ball_filling},
      {"bulk_packing", s.charge.bulk_packing},
      {"species", static_cast<int>(s.charge.species.size())}};
  // The settings the design's backend reads; the other backend's are left out.
  Json solver = Json{{"backend", s.solver.backend == Backend::Box2D ? "box2d" : "soft"},
                     {"time_step_s", s.solver.time_step_s}};
  if (s.solver.backend == Backend::Box2D) {
    solver["velocity_iterations"] = s.solver.velocity_iterations;
    solver["position_iterations"] = s.solver.position_iterations;
  } else {
    solver["substeps"] = s.solver.substeps;
    solver["contact_hertz"] = s.solver.contact_hertz;
    solver["contact_hertz_used"] = s.solver.contact_hertz_used();
    solver["damping_ratio"] = s.solver.damping_ratio;
    solver["push_out_radii_per_s"] = s.solver.push_out_radii_per_s;
    // The floor the charge's mass ratio sets under the push-out (from its sizes; the engine
    // takes the larger of the two, from the disks as filled).
    const double ratio = particle_mass_ratio(s);
    solver["particle_mass_ratio"] = ratio;
    solver["push_out_floor_m_s"] = ratio > 0.0 ? soft::carried_push_out_m_s(s.solver, ratio, 1.0) : 0.0;
  }
  solver["settle_time_s"] = s.solver.settle_time_s;
  solver["spinup_revolutions"] = s.solver.spinup_revolutions;
  solver["seed"] = static_cast<unsigned long long>(s.solver.seed);
  solver["size_cutoff_m"] = s.solver.size_cutoff_m;
  j["solver"] = std::move(solver);
  const WearDef& w = s.wear;
  j["wear"] = Json{
      {"mode", w.mode == WearMode::Staged ? "staged" : "continuous"},
      {"rate_source", w.rate_source == WearRateSource::Given          ? "given"
                          : w.rate_source == WearRateSource::AreaLossRate ? "area_loss_rate"
                                                                          : "height_loss_rate"},
      {"wear_rate_m3_per_J", w.wear_rate_m3_per_J},
      {"calibration_value", w.calibration_value},  // as the file gave it
      {"factor", w.factor},
      {"stage_hours", w.stage_hours},
      {"stages", w.stages},
      {"window_revolutions", w.window_revolutions},
      {"max_depth_step_m", w.max_depth_step_m},
      {"update_interval_s", w.update_interval_s},
      {"smoothing_radius_m", w.smoothing_radius_m},  // as given (0: the default)
      {"smoothing_radius_used_m", smoothing_radius(s)},
      {"average_rows", w.average_rows},
      {"shell_wear", w.shell_wear},
      {"shell_wear_rate_m3_per_J", w.shell_wear_rate_m3_per_J},
      {"start_hours", w.start_hours},
      {"replacement_height_m", w.replacement_height_m},
      {"liner_density_kg_m3", w.liner_density_kg_m3},
      {"target_rel_uncertainty", w.target_rel_uncertainty}};
  return j;
}

// A figure of summary.csv: its column (the error in COLUMN_se beside it), the estimate and the
// scale to the file's unit.
struct Column {
  const char* name;
  Estimate StageEstimate::*field;
  double scale;
};

const Column kColumns[] = {
    {"area_mm2", &StageEstimate::area_m2, 1e6},
    {"area_loss_pct", &StageEstimate::area_loss_fraction, 100.0},
    {"height_mm", &StageEstimate::height_m, 1e3},
    {"power_kw", &StageEstimate::power_W, 1e-3},
    {"collision_kw", &StageEstimate::collision_W, 1e-3},
    {"utilization", &StageEstimate::utilization, 1.0},
    {"liner_shear_kw", &StageEstimate::liner_shear_W, 1e-3},
    {"packed_shear_pct", &StageEstimate::packed_shear_share, 100.0},
    {"charge_t", &StageEstimate::charge_mass_kg, 1e-3},
    {"specific_power_kw_per_t", &StageEstimate::specific_power_W_per_kg, kW_per_t(1.0)},
    {"liner_wear_g_per_kwh", &StageEstimate::liner_wear_kg_per_J, g_per_kWh(1.0)},
    {"centre_of_mass_deg", &StageEstimate::centre_of_mass_deg, 1.0},
    {"toe_deg", &StageEstimate::toe_deg, 1.0},
    {"shoulder_deg", &StageEstimate::shoulder_deg, 1.0},
};
// Normalised to the reference design's new stage.
const Column kNormalised[] = {
    {"area_norm", &StageEstimate::area_m2, 1.0},
    {"power_norm", &StageEstimate::power_W, 1.0},
    {"collision_norm", &StageEstimate::collision_W, 1.0},
    {"utilization_norm", &StageEstimate::utilization, 1.0},
};

std::vector<std::string> summary_header(bool histories) {
  std::vector<std::string> h{"design"};
  if (histories) h.insert(h.end(), {"history", "replicate", "seed"});
  h.insert(h.end(), {"stage", "hours", "replicates", "error_source"});
  for (const Column& c : kColumns) h.insert(h.end(), {c.name, std::string(c.name) + "_se"});
  for (const Column& c : kNormalised) h.insert(h.end(), {c.name, std::string(c.name) + "_se"});
  h.insert(h.end(), {"life_h", "life_h_se", "life_extrapolated", "centrifuged"});
  return h;
}

// Kind k's cells of one stage row of `d` (empty where the design has no kind k).
void add_kind_cells(std::vector<io::CsvCell>& row, const DesignEstimate& d, const Scene* scene, std::size_t stage_index,
                    std::size_t k);

// The estimates' rows; `reference` normalises the *_norm columns; `scene` names the kinds
// of the kindK_ columns.
void add_rows(io::CsvTable& t, const DesignEstimate& d, const DesignEstimate* reference, const DesignReport* history,
              const Scene* scene, std::size_t kinds) {
  const StageEstimate* ref0 = reference && !reference->stages.empty() && reference->stages.front().stage == 0
                                  ? &reference->stages.front() : nullptr;
  for (std::size_t i = 0; i < d.stages.size(); ++i) {
    const StageEstimate& s = d.stages[i];
    std::vector<io::CsvCell> row{d.name};
    if (history)
      row.insert(row.end(), {history->name, history->replicate,
                             static_cast<long long>(history->scene->solver.seed)});
    row.insert(row.end(), {s.stage, s.hours, d.replicates, std::string(error_source_name(d.source))});
    for (const Column& c : kColumns) {
      const Estimate& e = s.*c.field;
      row.insert(row.end(), {e.mean * c.scale, e.se * c.scale});
    }
    for (const Column& c : kNormalised) {
      const Estimate& e = s.*c.field;
      const double by = ref0 ? (ref0->*c.field).mean : std::nan("");
      row.insert(row.end(), {e.mean / by, e.se / by});
    }
    row.insert(row.end(), {d.life_h.mean, d.life_h.se, d.life_extrapolated, s.centrifuged});
    for (std::size_t k = 0; k < kinds; ++k) add_kind_cells(row, d, scene, i, k);
    t.add_row(row);
  }
}

const DesignEstimate* find_estimate(const std::vector<DesignEstimate>& all, const std::string& name) {
  for (const DesignEstimate& d : all)
    if (d.name == name) return &d;
  return nullptr;
}

}  // namespace

namespace {

// summary.csv's columns of each kind of lifter of a pattern, after the common ones: each
// figure with its standard error, as the design's own.
const std::vector<std::string> kKindSummaryColumns = {
    "profile", "area_mm2", "area_mm2_se", "area_loss_pct", "area_loss_pct_se", "height_mm", "height_mm_se",
    "area_loss_rate_mm2_per_1000h", "area_loss_rate_mm2_per_1000h_se", "life_h", "life_h_se", "life_extrapolated"};

void add_kind_cells(std::vector<io::CsvCell>& row, const DesignEstimate& d, const Scene* scene, std::size_t stage_index,
                    std::size_t k) {
  const StageEstimate& s = d.stages[stage_index];
  if (!scene || k >= s.kinds.size() || static_cast<int>(k) >= scene->mill.kind_count()) {
    for (std::size_t i = 0; i < kKindSummaryColumns.size(); ++i) row.emplace_back(std::string());
    return;
  }
  const KindEstimate& e = s.kinds[k];
  const double per_1000h_mm2 = kSecondsPerHour * 1000.0 * 1e6;
  const Estimate life = k < d.kind_life_h.size() ? d.kind_life_h[k] : Estimate{};
  row.emplace_back(scene->mill.kind(static_cast<int>(k)).name);
  row.insert(row.end(), {e.area_m2.mean * 1e6, e.area_m2.se * 1e6, 100.0 * e.area_loss_fraction.mean,
                         100.0 * e.area_loss_fraction.se, e.height_m.mean * 1e3, e.height_m.se * 1e3,
                         e.area_loss_rate_m2_per_s.mean * per_1000h_mm2, e.area_loss_rate_m2_per_s.se * per_1000h_mm2,
                         life.mean, life.se});
  row.emplace_back(k < d.kind_life_extrapolated.size() ? bool(d.kind_life_extrapolated[k]) : true);
}

// The most kinds of any design with a pattern (0: none has one).
std::size_t pattern_kinds(const RunReport& report) {
  std::size_t kinds = 0;
  for (const DesignReport& d : report.designs)
    if (d.scene->mill.kind_count() > 1) kinds = std::max(kinds, static_cast<std::size_t>(d.scene->mill.kind_count()));
  return kinds;
}

std::vector<std::string> with_kind_columns(std::vector<std::string> header, std::size_t kinds) {
  for (std::size_t k = 0; k < kinds; ++k)
    for (const std::string& c : kKindSummaryColumns) header.push_back("kind" + std::to_string(k) + "_" + c);
  return header;
}

const DesignReport* find_history(const RunReport& report, const std::string& name) {
  for (const DesignReport& d : report.designs)
    if (d.name == name) return &d;
  return nullptr;
}

}  // namespace

// summary.csv: one row per design and stage, every figure with its standard error; with a
// pattern of kinds, every kind's lifter in kindK_ columns on the same row, with errors as the
// design's own (replicates folded).
void write_summary(const RunReport& report) {
  const std::size_t kinds = pattern_kinds(report);
  io::CsvTable t(with_kind_columns(summary_header(false), kinds));
  const DesignEstimate* ref = find_estimate(report.estimates, report.reference);
  for (const DesignEstimate& d : report.estimates) {
    const DesignReport* first = find_history(report, d.name);
    add_rows(t, d, ref, nullptr, first ? first->scene : nullptr, kinds);
  }
  t.write(io::summary_path(report.out));
}

std::string replicates_path(const std::string& out) { return io::join_path(out, "replicates.csv"); }

void write_replicates(const RunReport& report) {
  if (report.replicates < 2) return;
  const std::size_t kinds = pattern_kinds(report);
  io::CsvTable t(with_kind_columns(summary_header(true), kinds));
  const DesignEstimate* ref = find_estimate(report.estimates, report.reference);
  for (std::size_t i = 0; i < report.designs.size() && i < report.history_estimates.size(); ++i)
    add_rows(t, report.history_estimates[i], ref, &report.designs[i], report.designs[i].scene, kinds);
  t.write(replicates_path(report.out));
}

std::string verdicts_path(const std::string& out) { return io::join_path(out, "summary.md"); }

void write_verdicts(const RunReport& report) {
  std::string md = "# Comparison\n\n";
  if (report.estimates.size() < 2) {
    md += "One design: nothing to compare.\n";
  } else {
    md += "Each design against " + report.reference + ", with " +
          (report.replicates > 1 ? std::to_string(report.replicates) + " replicates per design (standard errors of their mean)"
                                 : std::string("one history per design (batch-means standard errors; "
                                               "`--replicates N` measures the spread between histories)")) +
          ". A difference is resolved when it exceeds " + io::format_number(kResolvedSigmas) +
          " combined standard errors" +
          (report.replicates > 1 ? std::string(" for many replicates; with few, Student's t at the same level "
                                               "instead (the threshold each verdict gives)")
                                 : std::string()) +
          ".\n\n";
    for (const Verdict& v : report.verdicts) md += "- " + v.text + "\n";
  }
  io::write_file_atomic(verdicts_path(report.out), md);
}

std::string kinds_path(const std::string& out) { return io::join_path(out, "kinds.csv"); }

void write_kinds(const RunReport& report) {
  bool any = false;
  for (const DesignReport& d : report.designs) any = any || d.scene->mill.kind_count() > 1;
  if (!any) return;
  io::CsvTable t({"design", "kind", "profile", "stage", "hours", "area_mm2", "area_loss_pct", "height_mm",
              "area_loss_rate_mm2_per_1000h", "life_h", "life_extrapolated", "replacement_height_mm"});
  for (const DesignReport& d : report.designs) {
    const int kinds = d.scene->mill.kind_count();
    if (kinds < 2) continue;
    const auto own0 = d.stages.find(0);
    for (int k = 0; k < kinds; ++k) {
      const auto idx = static_cast<std::size_t>(k);
      const double area0 = own0 != d.stages.end() && idx < own0->second.kinds.size()
                               ? in_mm2(own0->second.kinds[idx].area_m2) : std::nan("");
      const double life = idx < d.kind_life_h.size() ? d.kind_life_h[idx] : std::nan("");
      const bool extrapolated = idx < d.kind_life_extrapolated.size() ? d.kind_life_extrapolated[idx] : true;
      for (const auto& [stage, r] : d.stages) {
        if (idx >= r.kinds.size()) continue;
        const double area = in_mm2(r.kinds[idx].area_m2);
        const double rate = idx < r.kind_area_loss_rate_m2_per_s.size()
                                ? r.kind_area_loss_rate_m2_per_s[idx] * kSecondsPerHour * 1000.0 * 1e6 : std::nan("");
        t.add_row({d.name, k, d.scene->mill.kind(k).name, stage, r.hours, area, 100.0 * (1.0 - area / area0),
                   in_mm(r.kinds[idx].height_m), rate, life, extrapolated,
                   in_mm(d.scene->wear.replacement_height_m)});
      }
    }
  }
  t.write(kinds_path(report.out));
}

void check_run_of_scene(const std::string& run, const Scene& scene, const std::string& option) {
  const std::vector<std::string> changes = settings_changes(run, scene.name, scene);
  if (changes.empty()) return;
  std::string listed;
  for (const std::string& c : changes) listed += (listed.empty() ? "" : "; ") + c;
  throw InputError(run, option,
                   "a run of the scene as given now (with its --set and --fidelity), but the run's settings "
                   "differ (run -> scene): " + listed);
}

std::vector<std::string> settings_changes(const std::string& run, const std::string& design, const Scene& scene) {
  const std::string path = io::manifest_path(run);
  Json old_settings;
  try {
    const Json m = Json::parse(io::read_file(path));
    for (const auto& d : m.at("designs"))
      if (d.at("name") == design) old_settings = d.at("settings");
  } catch (const std::exception& e) {
    throw InputError(path, "designs", std::string("a manifest of `millwear run` that reads: ") + e.what());
  }
  if (old_settings.is_null())
    throw InputError(path, "designs", "a design named '" + design + "' (the scene's name)");
  const Json now = scene_settings(scene);
  std::vector<std::string> changes;
  for (const auto& [section, keys] : now.items())
    for (const auto& [key, value] : keys.items()) {
      const bool had = old_settings.contains(section) && old_settings[section].contains(key);
      // A run that did not record the lifter's shape (an older manifest) is judged by the name.
      if (!had && section == "mill" && key == "lifter_shape") continue;
      // Nor the smoothing radius it used: the given one (and the particles) still compare.
      if (!had && section == "wear" && key == "smoothing_radius_used_m") continue;
      const Json before = had ? old_settings[section][key] : Json();
      // Numbers compared as numbers (a JSON integer and a float of one value are the same).
      const bool same = had && (before == value || (before.is_number() && value.is_number() &&
                                                    before.get<double>() == value.get<double>()));
      if (same) continue;
      if (section == "mill" && key == "lifter_shape")  // hashes say nothing to a reader
        changes.push_back("mill.lifter_shape: a profile of other points, under the same name");
      else
        changes.push_back(section + "." + key + ": " + (had ? before.dump() : "(none)") + " -> " + value.dump());
    }
  return changes;
}

// spectrum.csv: the new stage's collision spectrum of each design.
void write_spectrum(const RunReport& report) {
  io::CsvTable t({"design", "stage", "hours", "energy_J_lower", "energy_J_upper", "count_per_s", "energy_W"});
  for (const DesignReport& d : report.designs) {
    // A scene that did not ask for the spectrum has none (zeros, not a measurement).
    if (!d.scene->outputs.collision_spectrum) continue;
    auto it = d.stages.find(0);
    if (it == d.stages.end()) continue;
    const StageRecord& r = it->second;
    const std::size_t n = std::min(r.spectrum_count_per_s.size(), r.spectrum_energy_W.size());
    for (std::size_t k = 0; k < n; ++k)
      t.add_row({d.name, 0, r.hours, spectrum_bin_lower_J(static_cast<int>(k)),
                 spectrum_bin_lower_J(static_cast<int>(k) + 1), r.spectrum_count_per_s[k],
                 r.spectrum_energy_W[k]});
  }
  t.write(io::spectrum_path(report.out));
}

namespace {

// A design's (or replicate's) entry: its inputs, seed and settings, status, lives, where it
// continued from, and each stage's time.
Json design_json(const DesignReport& d) {
  Json j;
  j["name"] = d.name;
  j["design"] = d.design;
  j["replicate"] = d.replicate;
  j["scene_file"] = d.input_files.front();
  j["input_files"] = d.input_files;
  Json copies = Json::array();
  for (const auto& f : d.input_copies) copies.push_back("inputs/" + f);
  j["input_copies"] = copies;
  j["seed"] = static_cast<unsigned long long>(d.scene->solver.seed);
  j["fidelity"] = d.scene->fidelity;
  j["set"] = d.scene->overrides;  // --set KEY=VALUE over the scene file, in order
  j["status"] = d.status;
  if (!d.error.empty()) j["error"] = d.error;
  j["resumed_stages"] = d.resumed_stages;
  j["life_h"] = number(d.life_h);
  j["life_extrapolated"] = d.life_extrapolated;
  // Life on the stages' clock, and what is left of it from where this history started.
  j["life_from_hours"] = d.life_from_hours;
  j["remaining_life_h"] = number(d.life_h - d.life_from_hours);
  if (d.scene->mill.kind_count() > 1) {
    Json kinds = Json::array();
    for (int k = 0; k < d.scene->mill.kind_count(); ++k) {
      const auto i = static_cast<std::size_t>(k);
      const double life = i < d.kind_life_h.size() ? d.kind_life_h[i] : std::nan("");
      kinds.push_back(Json{{"kind", k},
                           {"profile", d.scene->mill.kind(k).name},
                           {"life_h", number(life)},
                           {"remaining_life_h", number(life - d.life_from_hours)},
                           {"life_extrapolated", i < d.kind_life_extrapolated.size() ? bool(d.kind_life_extrapolated[i]) : true}});
    }
    j["kinds"] = kinds;
  }
  if (!d.continue_run.empty())
    j["continued_from"] = Json{{"run", d.continue_run},
                               {"stage", d.continue_stage},
                               {"hours", d.continue_hours},
                               {"changes", d.changes}};
  j["wear_rate_m3_per_J"] = number(d.wear_rate_m3_per_J);
  j["settings"] = scene_settings(*d.scene);
  Json stages = Json::array();
  for (const auto& [k, rec] : d.stages)
    stages.push_back(Json{{"stage", k},
                          {"hours", rec.hours},
                          {"wall_s", rec.wall_s},
                          {"simulated_s", rec.simulated_s},
                          {"disk_steps", static_cast<long long>(rec.disk_steps)},
                          {"resumed", k < d.resumed_stages}});
  j["stages"] = stages;
  j["events"] = d.events;
  return j;
}

// A design's estimate over its replicates, with the error's source, per stage.
Json estimate_json(const DesignEstimate& d) {
  Json j;
  j["name"] = d.name;
  j["replicates"] = d.replicates;
  j["error_source"] = error_source_name(d.source);
  j["life_h"] = number(d.life_h.mean);
  j["life_h_se"] = number(d.life_h.se);
  j["life_extrapolated"] = d.life_extrapolated;
  Json stages = Json::array();
  for (const StageEstimate& s : d.stages) {
    Json st{{"stage", s.stage}, {"hours", s.hours}};
    for (const Column& c : kColumns) {
      st[c.name] = number((s.*c.field).mean * c.scale);
      st[std::string(c.name) + "_se"] = number((s.*c.field).se * c.scale);
    }
    st["centrifuged"] = s.centrifuged;
    stages.push_back(st);
  }
  j["stages"] = stages;
  return j;
}

Json verdict_json(const Verdict& v) {
  return Json{{"figure", v.figure},
              {"unit", v.unit},
              {"stage", v.stage},
              {"hours", v.stage >= 0 ? Json(v.hours) : Json(nullptr)},
              {"design", v.design},
              {"reference", v.reference},
              {"value", number(v.value.mean)},
              {"value_se", number(v.value.se)},
              {"reference_value", number(v.reference_value.mean)},
              {"reference_value_se", number(v.reference_value.se)},
              {"difference", number(v.difference.value)},
              {"difference_se", number(v.difference.se)},
              {"threshold_se", number(v.difference.threshold)},
              {"resolved", v.difference.resolved},
              {"replicates_needed", v.difference.replicates_needed},
              {"replicates", v.replicates},
              {"error_source", error_source_name(v.source)},
              {"text", v.text}};
}

}  // namespace

void write_manifest(const RunReport& r) {
  Json m;
  m["program"] = "millwear";
  m["version"] = r.program_version;
  m["commit"] = r.program_commit;
  m["started"] = r.started;
  m["finished"] = r.finished;
  m["wall_s"] = r.wall_s;
  m["fidelity"] = r.fidelity;
  m["reference"] = r.reference;
  m["resumed"] = r.resumed;
  m["jobs"] = r.jobs;
  m["comparison_files"] = r.comparison_files;
  Json designs = Json::array();
  for (const DesignReport& d : r.designs) designs.push_back(design_json(d));
  m["designs"] = designs;
  m["replicates"] = r.replicates;
  Json estimates = Json::array();
  for (const DesignEstimate& d : r.estimates) estimates.push_back(estimate_json(d));
  m["estimates"] = estimates;
  Json verdicts = Json::array();
  for (const Verdict& v : r.verdicts) verdicts.push_back(verdict_json(v));
  m["verdicts"] = verdicts;
  m["files"] = r.files;
  // Invalid UTF-8 (a file name in a message) is replaced, never a failure to write.
  io::write_file_atomic(io::manifest_path(r.out), m.dump(2, ' ', false, Json::error_handler_t::replace) + "\n");
}

}  // namespace millwear::study
