#include "common/units.hpp"
#include "study/stage_files.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string_view>
#include <utility>

#include "common/errors.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/hash.hpp"
#include "io/run_folder.hpp"
#include "mill/mill.hpp"

namespace millwear::study {

namespace fs = std::filesystem;

namespace {

// The extensions of a stage's state files, after DESIGN_stageN (the marker, .done, aside).
constexpr const char* kStateExtensions[] = {".record", ".units.csv", ".spectrum.csv", ".edges.csv", ".charge.csv", ".start.csv"};

std::string stage_base(const std::string& out, const std::string& design, int stage) {
  return io::join_path(io::stages_dir(out), design + "_stage" + std::to_string(stage));
}

// The scalar doubles of a StageRecord, by name. One list for writing and reading, so the
// two can never disagree. (A field added to StageRecord must be added here to survive
// --resume.)
std::vector<std::pair<const char*, double*>> double_fields(StageRecord& r) {
  ChargeFigures& f = r.charge;
  ChargeSummary& s = f.summary;
  return {
      {"hours", &r.hours},
      {"lifter.area_m2", &r.lifter.area_m2},
      {"lifter.height_m", &r.lifter.height_m},
      {"lifter.leading_face_angle_rad", &r.lifter.leading_face_angle_rad},
      {"lifter.trailing_face_angle_rad", &r.lifter.trailing_face_angle_rad},
      {"charge.power_kW_per_m", &f.power_kW_per_m},
      {"charge.torque_arm_kW_per_m", &f.torque_arm_kW_per_m},
      {"charge.collision_kW_per_m", &f.collision_kW_per_m},
      {"charge.liner_kW_per_m", &f.liner_kW_per_m},
      {"charge.solver_kW_per_m", &f.solver_kW_per_m},
      {"charge.liner_shear_kW_per_m", &f.liner_shear_kW_per_m},
      {"charge_se.power_kW_per_m", &r.charge_errors.power_kW_per_m},
      {"charge_se.collision_kW_per_m", &r.charge_errors.collision_kW_per_m},
      {"charge_se.liner_shear_kW_per_m", &r.charge_errors.liner_shear_kW_per_m},
      {"charge_se.utilization", &r.charge_errors.utilization},
      {"charge_se.mass_kg", &r.charge_errors.mass_kg},
      {"charge_se.centre_of_mass_deg", &r.charge_errors.centre_of_mass_deg},
      {"charge_se.toe_deg", &r.charge_errors.toe_deg},
      {"charge_se.shoulder_deg", &r.charge_errors.shoulder_deg},
      {"charge_se.packed_shear_share", &r.charge_errors.packed_shear_share},
      {"summary.time_s", &s.time_s},
      {"summary.power_W", &s.power_W},
      {"summary.torque_Nm", &s.torque_Nm},
      {"summary.torque_arm_Nm", &s.torque_arm_Nm},
      {"summary.collision_power_W", &s.collision_power_W},
      {"summary.liner_dissipation_W", &s.liner_dissipation_W},
      {"summary.solver_dissipation_W", &s.solver_dissipation_W},
      {"summary.kinetic_change_W", &s.kinetic_change_W},
      {"summary.mass_kg", &s.mass_kg},
      {"summary.centre_of_mass_x_m", &s.centre_of_mass_m.x},
      {"summary.centre_of_mass_y_m", &s.centre_of_mass_m.y},
      {"summary.centre_of_mass_deg", &s.centre_of_mass_deg},
      {"summary.toe_deg", &s.toe_deg},
      {"summary.shoulder_deg", &s.shoulder_deg},
      {"summary.shear_work_rate_W", &s.shear_work_rate_W},
      {"summary.packed_shear_share", &s.packed_shear_share},
      {"summary.mean_packed_disks", &s.mean_packed_disks},
      {"area_loss_rate_m2_per_s", &r.area_loss_rate_m2_per_s},
      {"area_loss_rate_rel_sem", &r.area_loss_rate_rel_sem},
      {"liner_loss_rate_m2_per_s", &r.liner_loss_rate_m2_per_s},
      {"mill_angle_rad", &r.mill_angle_rad},
      {"wall_s", &r.wall_s},
      {"simulated_s", &r.simulated_s},
      {"snapshot.mill_angle_rad", &r.snapshot.mill_angle_rad},
      {"snapshot.mill_speed_rad_s", &r.snapshot.mill_speed_rad_s},
      {"snapshot.time_s", &r.snapshot.time_s},
  };
}

std::vector<std::pair<const char*, std::int64_t*>> integer_fields(StageRecord& r) {
  return {{"summary.escaped", &r.charge.summary.escaped},
          {"summary.non_finite", &r.charge.summary.non_finite},
          {"disk_steps", &r.disk_steps}};
}

const io::CsvOptions kExact{10, true};

struct Reader {
  io::KeyValues kv;
  std::string path;
  bool has(const std::string& key) const {
    for (const auto& [k, v] : kv)
      if (k == key) return true;
    return false;
  }
  std::string get(const std::string& key) const {
    for (const auto& [k, v] : kv)
      if (k == key) return v;
    throw InputError(path, key, "a value for " + key + " (a stage file of an earlier run)");
  }
  double number(const std::string& key) const {
    const std::string v = get(key);
    char* end = nullptr;
    const double d = std::strtod(v.c_str(), &end);
    // A stage's figures are finite: a NaN here is a damaged file, not a result ...
    const bool undefined = std::isnan(d) && (key.compare(0, kErrorPrefix.size(), kErrorPrefix) == 0 ||
                                             key == "summary.toe_deg" || key == "summary.shoulder_deg");
    if (v.empty() || *end != '\0' || !(std::isfinite(d) || undefined))
      throw InputError(path, key, "a finite number, found '" + v + "'");
    return d;
  }
  // ... but for the standard errors of the charge's figures, which are NaN where a figure has
  // none (the toe and shoulder of a window in which the charge centrifuged), and for the toe
  // and shoulder of a window in which no disk reached the shell band.
  static constexpr std::string_view kErrorPrefix = "charge_se.";
  long long integer(const std::string& key) const {
    const std::string v = get(key);
    char* end = nullptr;
    const long long i = std::strtoll(v.c_str(), &end, 10);
    if (v.empty() || *end != '\0') throw InputError(path, key, "an integer, found '" + v + "'");
    return i;
  }
};

// A charge state as exact CSV (one row per disk); the mill's angle, speed and time go in the
// record's key-values.
io::CsvTable charge_table(const ChargeState& st) {
  io::CsvTable charge({"x_m", "y_m", "vx_m_s", "vy_m_s", "angle_rad", "spin_rad_s", "radius_m",
                       "mass_kg", "species", "active"},
                      kExact);
  for (std::size_t i = 0; i < st.size(); ++i)
    charge.add_row({st.position_m[i].x, st.position_m[i].y, st.velocity_m_s[i].x,
                    st.velocity_m_s[i].y, st.angle_rad[i], st.spin_rad_s[i], st.radius_m[i],
                    st.mass_kg[i], static_cast<int>(st.species[i]), static_cast<int>(st.active[i])});
  return charge;
}

void read_charge_table(const io::CsvData& ch, ChargeState& st) {
  const auto ac = ch.finite_numbers("active");
  // A disk lost to a non-finite state stays in the file as it was, inactive: only the active
  // disks' numbers must be finite.
  const auto column = [&](const char* name) {
    const std::size_t c = ch.column(name);
    std::vector<double> v(ch.row_count());
    for (std::size_t i = 0; i < v.size(); ++i) v[i] = ac[i] != 0.0 ? ch.finite_number(i, c) : ch.number(i, c);
    return v;
  };
  const auto x = column("x_m"), y = column("y_m"), vx = column("vx_m_s"), vy = column("vy_m_s"),
             sp = ch.finite_numbers("species");
  st.angle_rad = column("angle_rad");
  st.spin_rad_s = column("spin_rad_s");
  st.radius_m = ch.finite_numbers("radius_m");
  st.mass_kg = ch.finite_numbers("mass_kg");
  for (std::size_t i = 0; i < x.size(); ++i) {
    st.position_m.push_back({x[i], y[i]});
    st.velocity_m_s.push_back({vx[i], vy[i]});
    st.species.push_back(static_cast<std::uint8_t>(sp[i]));
    st.active.push_back(static_cast<std::uint8_t>(ac[i]));
  }
}

// The key of a stage marker that holds a state file's content hash: "hash.units.csv".
std::string hash_key(const std::string& ext) { return "hash" + ext; }

// The state files of a stage, by extension, as they will be written.
using StateFiles = std::vector<std::pair<std::string, std::string>>;

// The marker key of a content hash a stage is being rewritten to: "next.hash.record".
std::string next_hash_key(const std::string& ext) { return "next." + hash_key(ext); }

// The content hashes a stage marker holds (hash.EXT=); none in a marker written without them.
struct StageHashes {
  io::KeyValues marker;
  std::string path;
  bool any = false;  // the marker holds hashes: every state file must have its own
  bool has(const std::string& ext) const { return !io::find_value(marker, hash_key(ext)).empty(); }
};

StageHashes read_stage_hashes(const std::string& marker_path) {
  StageHashes h;
  h.path = marker_path;
  if (io::file_exists(marker_path)) h.marker = io::read_key_values(marker_path);
  for (const auto& kv : h.marker) h.any = h.any || kv.first.rfind("hash.", 0) == 0;
  return h;
}

// A state file of a finished stage, checked against the content hash its marker records:
// a file changed or cut after the stage finished (even at a line end, where it would still
// parse) is refused by name instead of resuming from other numbers, and so is a marker that
// holds hashes but none for this file. A marker without any hash is taken as it is.
std::string read_state_file(const std::string& base, const std::string& ext, const StageHashes& hashes) {
  std::string content = io::read_file(base + ext);
  if (!hashes.any) return content;
  const std::string recorded = io::find_value(hashes.marker, hash_key(ext));
  if (recorded.empty())
    throw InputError(hashes.path, hash_key(ext), "the content hash of " + base + ext + " (the marker was edited)");
  // A stop while a finished stage was written again leaves each file old or new.
  const std::string actual = io::stable_hash_hex(content);
  if (recorded != actual && io::find_value(hashes.marker, next_hash_key(ext)) != actual)
    throw InputError(base + ext, "",
                     "the content recorded in " + hashes.path + " (the file was changed or cut after its stage finished)");
  return content;
}

}  // namespace

void write_stage_state(const std::string& out, const std::string& design, const StageRecord& rec_in) {
  StageRecord rec = rec_in;  // the field table wants a mutable record; copies are cheap enough
  const std::string base = stage_base(out, design, rec.stage);
  io::ensure_dir(io::stages_dir(out));
  StateFiles files;

  io::CsvTable units({"unit", "x_m", "y_m"}, kExact);
  for (std::size_t u = 0; u < rec.units.size(); ++u)
    for (const Vec2& p : rec.units[u].surface) units.add_row({u, p.x, p.y});
  files.emplace_back(".units.csv", units.str());

  io::CsvTable spec({"bin", "count_per_s", "energy_W"}, kExact);
  const std::size_t nbins = std::max(rec.spectrum_count_per_s.size(), rec.spectrum_energy_W.size());
  for (std::size_t k = 0; k < nbins; ++k)
    spec.add_row({k, k < rec.spectrum_count_per_s.size() ? rec.spectrum_count_per_s[k] : 0.0,
                  k < rec.spectrum_energy_W.size() ? rec.spectrum_energy_W[k] : 0.0});
  files.emplace_back(".spectrum.csv", spec.str());

  io::CsvTable edges({"edge", "wear_rate_m_per_s"}, kExact);
  for (std::size_t e = 0; e < rec.edge_wear_rate_m_per_s.size(); ++e)
    edges.add_row({e, rec.edge_wear_rate_m_per_s[e]});
  files.emplace_back(".edges.csv", edges.str());

  files.emplace_back(".charge.csv", charge_table(rec.snapshot).str());
  const bool carried = rec.start_charge.size() > 0;
  if (carried) files.emplace_back(".start.csv", charge_table(rec.start_charge).str());

  io::KeyValues kv;
  kv.emplace_back("stage", std::to_string(rec.stage));
  kv.emplace_back("units", std::to_string(rec.units.size()));
  for (std::size_t u = 0; u < rec.units.size(); ++u)
    kv.emplace_back("unit." + std::to_string(u) + ".lifter_half_base_m",
                    io::format_exact(rec.units[u].lifter_half_base_m));
  for (auto& [k, p] : double_fields(rec)) kv.emplace_back(k, io::format_exact(*p));
  for (auto& [k, p] : integer_fields(rec)) kv.emplace_back(k, std::to_string(*p));
  kv.emplace_back("worn_out", rec.worn_out ? "1" : "0");
  const auto add_worn = [&kv](const std::string& pre, const WornError& e) {
    if (std::isfinite(e.area_m2)) kv.emplace_back(pre + "worn_area_se_m2", io::format_exact(e.area_m2));
    if (std::isfinite(e.height_m)) kv.emplace_back(pre + "worn_height_se_m", io::format_exact(e.height_m));
  };
  add_worn("", rec.worn_se);
  kv.emplace_back("summary.centrifuged", rec.charge.summary.centrifuged ? "1" : "0");
  kv.emplace_back("kinds", std::to_string(rec.kinds.size()));
  for (std::size_t k = 0; k < rec.kinds.size(); ++k) {
    const std::string pre = "kind." + std::to_string(k) + ".";
    kv.emplace_back(pre + "area_m2", io::format_exact(rec.kinds[k].area_m2));
    kv.emplace_back(pre + "height_m", io::format_exact(rec.kinds[k].height_m));
    kv.emplace_back(pre + "leading_face_angle_rad", io::format_exact(rec.kinds[k].leading_face_angle_rad));
    kv.emplace_back(pre + "trailing_face_angle_rad", io::format_exact(rec.kinds[k].trailing_face_angle_rad));
    kv.emplace_back(pre + "area_loss_rate_m2_per_s",
                    io::format_exact(k < rec.kind_area_loss_rate_m2_per_s.size() ? rec.kind_area_loss_rate_m2_per_s[k] : 0.0));
    if (k < rec.kind_area_loss_rate_rel_sem.size())
      kv.emplace_back(pre + "area_loss_rate_rel_sem", io::format_exact(rec.kind_area_loss_rate_rel_sem[k]));
    if (k < rec.kind_worn_se.size()) add_worn(pre, rec.kind_worn_se[k]);
  }
  if (carried) {
    kv.emplace_back("start.mill_angle_rad", io::format_exact(rec.start_charge.mill_angle_rad));
    kv.emplace_back("start.mill_speed_rad_s", io::format_exact(rec.start_charge.mill_speed_rad_s));
    kv.emplace_back("start.time_s", io::format_exact(rec.start_charge.time_s));
  }
  files.emplace_back(".record", io::format_key_values(kv, "millwear stage record (exact)"));

  // A finished stage written again (a resumed stage worn through anew, its record holding the
  // new wear's errors): its marker first takes the new contents' hashes beside the old, so a
  // stop while the files are replaced leaves each one matching the marker.
  io::KeyValues hashes;
  for (const auto& [ext, content] : files) hashes.emplace_back(hash_key(ext), io::stable_hash_hex(content));
  // A marker that does not read marks no finished stage (io::list_finished_stages): the
  // stage is being written as a new one, and the marker goes before its files are replaced.
  const std::string marker_path = io::stage_done_marker(out, design, rec.stage);
  std::optional<io::KeyValues> old_marker;
  if (io::file_exists(marker_path)) try {
      old_marker = io::read_key_values(marker_path);
    } catch (const InputError&) {
      std::error_code ec;
      fs::remove(marker_path, ec);
    }
  if (old_marker) {
    io::KeyValues pending;
    for (const auto& kv_old : *old_marker)  // design= and stage= come anew
      if (kv_old.first.rfind("next.", 0) != 0 && kv_old.first != "design" && kv_old.first != "stage")
        pending.push_back(kv_old);
    for (const auto& [key, hash] : hashes) pending.emplace_back("next." + key, hash);
    io::write_stage_done(out, design, rec.stage, pending);
  }
  for (const auto& [ext, content] : files) io::write_file_atomic(base + ext, content);

  // Last: the marker says every file above is complete, and holds their content hashes.
  io::KeyValues marker{{"hours", io::format_number(rec.hours)},
                       {"wall_s", io::format_number(rec.wall_s, 6)},
                       {"files", design + "_stage" + std::to_string(rec.stage) +
                                     ".{record,units.csv,spectrum.csv,edges.csv,charge.csv" +
                                     (carried ? ",start.csv}" : "}")}};
  marker.insert(marker.end(), hashes.begin(), hashes.end());
  io::write_stage_done(out, design, rec.stage, marker);
}

StageRecord read_stage_state(const std::string& out, const std::string& design, int stage) {
  const std::string base = stage_base(out, design, stage);
  const StageHashes hashes = read_stage_hashes(io::stage_done_marker(out, design, stage));
  const auto read_state = [&](const std::string& ext) { return read_state_file(base, ext, hashes); };
  const auto read_state_csv = [&](const std::string& ext) { return io::parse_csv(read_state(ext), base + ext); };
  StageRecord rec;
  Reader r{io::parse_key_values(read_state(".record"), base + ".record"), base + ".record"};
  rec.stage = static_cast<int>(r.integer("stage"));
  if (rec.stage != stage) throw InputError(r.path, "stage", "stage=" + std::to_string(stage));
  const long long nunits = r.integer("units");
  if (nunits < 1 || nunits > 100000)
    throw InputError(r.path, "units", "a unit count in [1, 100000], found " + std::to_string(nunits));
  rec.units.resize(static_cast<std::size_t>(nunits));
  for (long long u = 0; u < nunits; ++u)
    rec.units[static_cast<std::size_t>(u)].lifter_half_base_m =
        r.number("unit." + std::to_string(u) + ".lifter_half_base_m");
  for (auto& [k, p] : double_fields(rec)) *p = r.number(k);
  for (auto& [k, p] : integer_fields(rec)) *p = r.integer(k);
  rec.worn_out = r.integer("worn_out") != 0;
  // A stage not worn through (the last) has no worn errors, nor has a record older than the keys.
  const auto read_worn = [&r](const std::string& pre) {
    WornError e;
    if (r.has(pre + "worn_area_se_m2")) e.area_m2 = r.number(pre + "worn_area_se_m2");
    if (r.has(pre + "worn_height_se_m")) e.height_m = r.number(pre + "worn_height_se_m");
    return e;
  };
  rec.worn_se = read_worn("");
  rec.charge.summary.centrifuged = r.integer("summary.centrifuged") != 0;
  const long long kinds = r.has("kinds") ? r.integer("kinds") : 0;
  if (kinds < 0 || kinds > nunits) throw InputError(r.path, "kinds", "a count of kinds of lifter up to the unit count");
  for (long long k = 0; k < kinds; ++k) {
    const std::string pre = "kind." + std::to_string(k) + ".";
    LifterMetrics m;
    m.area_m2 = r.number(pre + "area_m2");
    m.height_m = r.number(pre + "height_m");
    m.leading_face_angle_rad = r.number(pre + "leading_face_angle_rad");
    m.trailing_face_angle_rad = r.number(pre + "trailing_face_angle_rad");
    rec.kinds.push_back(m);
    rec.kind_area_loss_rate_m2_per_s.push_back(r.number(pre + "area_loss_rate_m2_per_s"));
    if (r.has(pre + "area_loss_rate_rel_sem"))
      rec.kind_area_loss_rate_rel_sem.push_back(r.number(pre + "area_loss_rate_rel_sem"));
    rec.kind_worn_se.push_back(read_worn(pre));
  }

  io::CsvData units = read_state_csv(".units.csv");
  {
    const std::size_t uc = units.column("unit"), xc = units.column("x_m"), yc = units.column("y_m");
    for (std::size_t i = 0; i < units.row_count(); ++i) {
      const double u = units.finite_number(i, uc);
      if (!(u >= 0 && u < static_cast<double>(nunits)))
        throw InputError(units.path, "line " + std::to_string(units.row_line[i]),
                         "a unit index below " + std::to_string(nunits));
      rec.units[static_cast<std::size_t>(u)].surface.push_back({units.finite_number(i, xc), units.finite_number(i, yc)});
    }
  }
  io::CsvData spec = read_state_csv(".spectrum.csv");
  rec.spectrum_count_per_s = spec.finite_numbers("count_per_s");
  rec.spectrum_energy_W = spec.finite_numbers("energy_W");
  rec.edge_wear_rate_m_per_s = read_state_csv(".edges.csv").finite_numbers("wear_rate_m_per_s");

  read_charge_table(read_state_csv(".charge.csv"), rec.snapshot);
  // A stage that started from the previous stage's charge has it in .start.csv (the marker
  // says so where it holds hashes: a start.csv gone missing is not a fresh fill).
  if (hashes.any ? hashes.has(".start.csv") : io::file_exists(base + ".start.csv")) {
    read_charge_table(read_state_csv(".start.csv"), rec.start_charge);
    rec.start_charge.mill_angle_rad = r.number("start.mill_angle_rad");
    rec.start_charge.mill_speed_rad_s = r.number("start.mill_speed_rad_s");
    rec.start_charge.time_s = r.number("start.time_s");
  }
  return rec;
}

std::vector<std::string> stage_state_files(const std::string& out, const std::string& design, int stage) {
  const std::string base = stage_base(out, design, stage);
  std::vector<std::string> files;
  for (const char* ext : kStateExtensions)
    if (io::file_exists(base + ext)) files.push_back(base + ext);
  const std::string marker = io::stage_done_marker(out, design, stage);
  if (io::file_exists(marker)) files.push_back(marker);
  return files;
}

std::vector<std::string> stage_file_names(const std::string& design, int stage) {
  const std::string base = design + "_stage" + std::to_string(stage);
  std::vector<std::string> names;
  for (const char* ext : kStateExtensions) names.push_back("stages/" + base + ext);
  names.push_back("stages/" + base + ".done");
  names.push_back("profiles/" + base + ".csv");
  return names;
}

namespace {

// What follows DESIGN_stage<digits> in a name ("" if it is not one): not another design whose
// name starts the same way.
std::string_view after_stage_number(const std::string& name, const std::string& design) {
  const std::string prefix = design + "_stage";
  if (name.compare(0, prefix.size(), prefix) != 0) return {};
  std::size_t i = prefix.size();
  if (i >= name.size() || !std::isdigit(static_cast<unsigned char>(name[i]))) return {};
  while (i < name.size() && std::isdigit(static_cast<unsigned char>(name[i]))) ++i;
  return std::string_view(name).substr(i);
}

}  // namespace

bool is_stage_profile_name(const std::string& name, const std::string& design) {
  return after_stage_number(name, design) == ".csv";
}

bool is_stage_state_name(const std::string& name, const std::string& design) {
  // Not a file of the user's under a name the run never writes.
  const std::string_view ext = after_stage_number(name, design);
  if (ext.empty()) return false;
  if (ext == ".done") return true;
  for (const char* e : kStateExtensions)
    if (ext == e) return true;
  return false;
}

void remove_stage_state(const std::string& out, const std::string& design) {
  std::error_code ec;
  const std::string dir = io::stages_dir(out);
  if (!fs::is_directory(dir, ec)) return;
  std::vector<fs::path> doomed;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (is_stage_state_name(e.path().filename().string(), design)) doomed.push_back(e.path());
  // Markers first, so a half-removed stage is never taken for a finished one.
  for (const auto& p : doomed)
    if (p.extension() == ".done") fs::remove(p, ec);
  for (const auto& p : doomed) fs::remove(p, ec);
  // Profiles of the earlier run would otherwise be drawn as extra stages.
  const std::string pdir = io::profiles_dir(out);
  if (fs::is_directory(pdir, ec))
    for (const auto& e : fs::directory_iterator(pdir, ec))
      if (is_stage_profile_name(e.path().filename().string(), design)) fs::remove(e.path(), ec);
}

std::string profile_csv_text(const StageRecord& rec) {
  io::CsvTable t({"x_mm", "y_mm"});
  if (!rec.units.empty()) {
    const LinerUnit& u = rec.units.front();
    const double xmax = kProfileMargin * u.lifter_half_base_m;
    for (const Vec2& p : u.surface)
      if (std::fabs(p.x) <= xmax) t.add_row({p.x * 1e3, p.y * 1e3});
  }
  return t.str();
}

void write_profile_csv(const std::string& out, const std::string& design, const StageRecord& rec) {
  io::ensure_dir(io::profiles_dir(out));
  io::write_file_atomic(io::profile_path(out, design, rec.stage), profile_csv_text(rec));
}

void write_snapshot_table(const std::string& path, const ChargeState& st, const std::vector<SpeciesDef>& species) {
  io::CsvTable t({"x_m", "y_m", "radius_m", "species", "species_name", "ball"});
  for (std::size_t i = 0; i < st.size(); ++i) {
    if (!st.active[i]) continue;
    const int s = st.species[i];
    const bool known = s < static_cast<int>(species.size());
    t.add_row({st.position_m[i].x, st.position_m[i].y, st.radius_m[i], s, known ? species[s].name : "?",
               known && species[s].is_ball ? 1 : 0});
  }
  t.write(path);
}

SnapshotMarks snapshot_marks(const ChargeSummary& summary, double mill_speed_rad_s) {
  SnapshotMarks m;
  m.toe_deg = summary.toe_deg;
  m.shoulder_deg = summary.shoulder_deg;
  m.centrifuged = summary.centrifuged;
  m.centre_of_mass_m = summary.centre_of_mass_m;
  m.turning = mill_speed_rad_s > 0.0 ? 1 : mill_speed_rad_s < 0.0 ? -1 : 0;
  return m;
}

void write_liner_table(const std::string& path, const MillGeometry& mill, double mill_angle_rad,
                       const std::string& value_column, const std::vector<double>& value_per_edge,
                       int stage, double hours, const SnapshotMarks& marks) {
  io::CsvTable t({"edge", "owner", "x1_m", "y1_m", "x2_m", "y2_m", value_column, "stage", "hours",
                  "mill_angle_rad", "toe_deg", "shoulder_deg", "centrifuged", "com_x_m", "com_y_m", "turning"});
  const std::size_t n = mill.boundary.size();
  for (std::size_t e = 0; e < n; ++e) {
    const Vec2 a = rotated(mill.boundary[e], mill_angle_rad);
    const Vec2 b = rotated(mill.boundary[(e + 1) % n], mill_angle_rad);
    const double v = e < value_per_edge.size() ? value_per_edge[e] : std::nan("");
    t.add_row({e, mill.edges[e].owner == EdgeOwner::Lifter ? "lifter" : "shell", a.x, a.y, b.x, b.y, v, stage,
               hours, mill_angle_rad, marks.toe_deg, marks.shoulder_deg, marks.centrifuged ? 1 : 0,
               marks.centre_of_mass_m.x, marks.centre_of_mass_m.y, marks.turning});
  }
  t.write(path);
}

void write_snapshot_csv(const std::string& out, const std::string& design, const Scene& scene,
                        const StageRecord& rec) {
  write_snapshot_table(io::snapshot_path(out, design), rec.snapshot, scene.charge.species);
}

void write_liner_csv(const std::string& out, const std::string& design, const Scene& scene,
                     const StageRecord& rec) {
  MillGeometry mill;
  if (!rec.units.empty()) mill = build_mill(scene.radius_m(), scene.mill.rows, rec.units, scene.mill.kind_count());
  std::vector<double> rate;
  for (double w : rec.edge_wear_rate_m_per_s) rate.push_back(mm_per_1000h(w));
  write_liner_table(io::liner_path(out, design), mill, rec.mill_angle_rad, "wear_rate_mm_per_1000h", rate, rec.stage,
                    rec.hours, snapshot_marks(rec.charge.summary, rec.snapshot.mill_speed_rad_s));
}

void check_stage_of_scene(const StageRecord& rec, const Scene& scene, const std::string& run,
                          const std::string& option) {
  if (rec.units.empty()) return;  // a worn-out marker holds no liner
  const double pitch = 2.0 * kPi * scene.radius_m() / scene.mill.rows;
  const auto kinds = static_cast<std::size_t>(scene.mill.kind_count());
  // One unit per kind when the rows of a kind wear as one (wear.average_rows), else one per row.
  const std::size_t units = scene.wear.average_rows ? kinds : static_cast<std::size_t>(scene.mill.rows);
  double width = 0.0;
  for (const LinerUnit& u : rec.units)
    if (!u.surface.empty()) width = std::max(width, u.surface.back().x - u.surface.front().x);
  if (rec.units.size() == units && std::abs(width - pitch) <= 1e-6 * pitch) return;
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "a run of this scene's mill (%zu lifter kind(s), %d rows, %.4g m, %zu liner unit(s)): its stage %d "
                "of design '%s' has %zu liner unit(s) %.1f mm wide, where the scene's pitch is %.1f mm",
                kinds, scene.mill.rows, scene.mill.diameter_m, units, rec.stage, scene.name.c_str(), rec.units.size(),
                width * 1e3, pitch * 1e3);
  throw InputError(run, option, buf);
}

}  // namespace millwear::study
