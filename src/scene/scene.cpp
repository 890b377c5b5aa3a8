// Scene files (TOML) -> a validated Scene in SI units.
//
// Every key is read through a TableReader that knows the table's allowed keys, so an unknown
// key, a wrong type and an out-of-range value all fail here with the file, the dotted key
// ("charge.species[1].density"), the expectation in the file's units and the line. Units are
// converted in exactly one place each: mm -> m, hours stay hours (named *_hours), rpm ->
// fraction of critical speed. The scene type and its users see no toml++ type; the readers of
// other input files (profiles, screens, comparisons) parse their own tables.
#include "common/units.hpp"
#include "scene/scene.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <cctype>
#include <limits>
#include <map>
#include <optional>
#include <sstream>

#include <toml++/toml.h>

#include "common/errors.hpp"
#include "common/names.hpp"
#include "scene/fidelity.hpp"
#include "scene/filling.hpp"
#include "scene/limits.hpp"
#include "scene/table_reader.hpp"

namespace millwear {

namespace fs = std::filesystem;


// ---------------------------------------------------------------------------------------
// Derived quantities
// ---------------------------------------------------------------------------------------

namespace {

// The listed sizes that get disks: those with a share of the species' mass (all of them if
// none has one, which the reader refuses).
std::vector<double> sizes_with_mass(const SpeciesDef& s) {
  std::vector<double> out;
  for (std::size_t i = 0; i < s.diameters_m.size(); ++i)
    if (i >= s.mass_fractions.size() || s.mass_fractions[i] > 0.0) out.push_back(s.diameters_m[i]);
  return out.empty() ? s.diameters_m : out;
}

}  // namespace

double SpeciesDef::smallest_diameter_m() const {
  if (diameters_m.empty()) return d_min_m;
  const std::vector<double> d = sizes_with_mass(*this);
  return *std::min_element(d.begin(), d.end());
}

double SpeciesDef::largest_diameter_m() const {
  if (diameters_m.empty()) return d_max_m;
  const std::vector<double> d = sizes_with_mass(*this);
  return *std::max_element(d.begin(), d.end());
}

SpeciesDef SpeciesDef::without_sizes_below(double cutoff_m) const {
  SpeciesDef out = *this;
  if (cutoff_m <= 0.0) return out;
  if (diameters_m.empty()) {
    out.d_min_m = std::max(d_min_m, std::min(cutoff_m, d_max_m));
    return out;
  }
  out.diameters_m.clear();
  out.mass_fractions.clear();
  double kept = 0.0;
  for (std::size_t i = 0; i < diameters_m.size(); ++i) {
    if (!size_kept(diameters_m[i], cutoff_m)) continue;
    out.diameters_m.push_back(diameters_m[i]);
    out.mass_fractions.push_back(mass_fractions[i]);
    kept += mass_fractions[i];
  }
  if (kept > 0.0)
    for (double& f : out.mass_fractions) f /= kept;
  return out;
}

double Scene::critical_speed_rad_s() const { return std::sqrt(kGravity / radius_m()); }

double Scene::angular_speed_rad_s() const {
  return mill.speed_fraction_critical * critical_speed_rad_s();
}

double Scene::revolution_time_s() const { return 2.0 * kPi / angular_speed_rad_s(); }

double Scene::slice_thickness() const {
  return mill.slice_thickness_m > 0.0 ? mill.slice_thickness_m
                                      : 2.0 * largest_particle_radius_m();
}

bool MillDef::one_lifter_shape() const {
  for (int k = 1; k < kind_count(); ++k) {
    const Polyline& a = kind(0).points;
    const Polyline& b = kind(k).points;
    if (a.size() != b.size()) return false;
    for (std::size_t i = 0; i < a.size(); ++i)
      if (a[i].x != b[i].x || a[i].y != b[i].y) return false;
  }
  return true;
}

bool Scene::species_in_use(const SpeciesDef& s) const {
  return s.is_ball ? charge.ball_filling > 0.0 : charge.filling > charge.ball_filling;
}

std::vector<SpeciesDef> Scene::species_as_placed() const {
  std::vector<SpeciesDef> out;
  out.reserve(charge.species.size());
  for (const auto& s : charge.species)
    out.push_back(s.is_ball ? s : s.without_sizes_below(solver.size_cutoff_m));
  return out;
}

double Scene::smallest_particle_radius_m() const {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& s : species_as_placed())
    if (species_in_use(s)) d = std::min(d, s.smallest_diameter_m());
  return std::isfinite(d) ? 0.5 * d : 0.0;
}

double Scene::largest_particle_radius_m() const {
  double d = 0.0;
  for (const auto& s : species_as_placed())
    if (species_in_use(s)) d = std::max(d, s.largest_diameter_m());
  return 0.5 * d;
}

LinerUnit new_liner_unit(const Scene& scene, int kind) {
  const LifterProfile& lifter = scene.mill.kind(kind);
  if (lifter.unit_pitch_m > 0.0) {
    // A whole unit's scan states its pitch: it must be the mill's.
    const double pitch = 2.0 * kPi * scene.radius_m() / scene.mill.rows;
    if (std::abs(lifter.unit_pitch_m - pitch) > kPitchTolerance * pitch)
      throw InputError(lifter.source_file, "line " + std::to_string(lifter.pitch_line),
                       "pitch_mm = " + toml_reader::num_text(in_mm(lifter.unit_pitch_m)) + ": the pitch of the lifters of " +
                           scene.source_file + " (within " + toml_reader::num_text(100.0 * kPitchTolerance) +
                           "%), whose " + std::to_string(scene.mill.rows) + " rows on a " +
                           toml_reader::num_text(scene.mill.diameter_m) + " m mill stand " +
                           toml_reader::num_text(pitch * 1e3) + " mm apart at the shell");
  }
  // A scan of one lifter (no pitch line) is in lifter-local coordinates, as the surveys are:
  // x = 0 on the lifter's centre line. make_measured_unit takes it as it is, so scan and
  // surveys stay in one frame (the midpoint of a worn lifter's feet is not its centre line: a
  // worn face moves its foot). Refused only a scan whose lifter cannot stand in its row about
  // x = 0: x = 0 outside its metal, or the lifter wider than the pitch about x = 0 though it
  // would fit centred (a lifter too wide either way is refused by make_measured_unit).
  if (!lifter.measured.empty() && lifter.unit_pitch_m <= 0.0 && lifter.points.size() >= 2) {
    const double pitch = 2.0 * kPi * scene.radius_m() / scene.mill.rows;
    const double left = lifter.points.front().x, right = lifter.points.back().x;
    const double half_extent = std::max(-left, right);
    const bool outside = !(left < 0.0 && right > 0.0);
    if (outside || (2.0 * half_extent >= pitch && right - left < pitch)) {
      const auto mm = [](double m) { return toml_reader::num_text(in_mm(m)); };
      const std::string why =
          outside ? "x = 0 is outside its metal"
                  : "about x = 0 it reaches " + mm(half_extent) + " mm to one side, past half the pitch (" +
                        mm(0.5 * pitch) + " mm), so it would not stand in its row";
      throw InputError(lifter.source_file, "x_mm",
                       "expected a scan of one lifter with x_mm = 0 on the lifter's centre line, as in the surveys "
                       "compared with its history (the scan is taken as measured, not moved): its feet are at x = " +
                           mm(left) + " and " + mm(right) + " mm, and " + why + "; give x_mm from the lifter's "
                           "centre line, in the scan and in the surveys taken with the same gauge (" +
                           scene.source_file + ", " + scene.mill.profile_key(kind) + ")");
    }
  }
  try {
    if (!lifter.measured.empty())
      return make_measured_unit(lifter.measured, lifter.points, scene.radius_m(), scene.mill.rows, scene.mill.mesh,
                                lifter.unit_pitch_m > 0.0);
    return make_liner_unit(lifter.points, scene.radius_m(), scene.mill.rows, scene.mill.mesh);
  } catch (const InputError& e) {
    // The mill module does not know which file asked for this lifter; say it.
    if (!e.file.empty()) throw;
    std::string where = e.where.empty() ? "lifters" : e.where;
    if (where == "lifters.profile") where = scene.mill.profile_key(kind);
    throw InputError(scene.source_file, where, e.expected + " (profile '" + lifter.name + "')");
  }
}

MillGeometry build_scene_mill(const Scene& scene) {
  std::vector<LinerUnit> units;
  for (int k = 0; k < scene.mill.kind_count(); ++k) units.push_back(new_liner_unit(scene, k));
  return build_mill(scene.radius_m(), scene.mill.rows, std::move(units), scene.mill.kind_count());
}

// ---------------------------------------------------------------------------------------
// Reading
// ---------------------------------------------------------------------------------------

namespace {

using namespace toml_reader;  // Bounds, TableReader and the message helpers


// kMaxHours (scene/limits.hpp) bounds every time in hours; 1e4 revolutions every count of
// revolutions (the step counts they give are bounded again in scene/limits.hpp).
constexpr double kMaxRevolutions = 1e4;

const toml::table kEmpty;

// Exactly one of two keys (both or neither is an error).
void exactly_one(const TableReader& r, const char* a, const char* b, const std::string& what) {
  if (r.has(a) && r.has(b))
    r.fail(b, "only one of '" + r.full(a) + "' and '" + r.full(b) + "' (" + what + ")");
  if (!r.has(a) && !r.has(b))
    r.missing(a, "one of '" + r.full(a) + "' or '" + r.full(b) + "' (" + what + ")");
}

void read_mill(const TableReader& r, Scene& s) {
  MillDef& m = s.mill;
  // 0.05 m: below any laboratory mill; 50 m: above the largest mill built.
  m.diameter_m = r.need_number("diameter", closed(0.05, 50.0), "m, inside the shell");
  m.length_m = r.need_number("length", open_closed(0.0, 50.0), "m, belly length");
  if (auto v = r.number("slice_thickness", closed(0.0, 50.0), "m; 0 = largest particle diameter"))
    m.slice_thickness_m = *v;
  exactly_one(r, "speed", "speed_rpm", "mill speed");
  if (auto v = r.number("speed", closed(kMinSpeedFraction, kMaxSpeedFraction), "fraction of critical speed"))
    m.speed_fraction_critical = *v;
  if (r.has("speed_rpm")) {
    const double crit_rpm = rpm_from_rad_s(std::sqrt(kGravity / (0.5 * m.diameter_m)));
    const double rpm = *r.number("speed_rpm", closed(kMinSpeedFraction * crit_rpm, kMaxSpeedFraction * crit_rpm),
                                 "rpm; critical speed of this mill is " + num_text(crit_rpm) + " rpm");
    m.speed_fraction_critical = rpm / crit_rpm;
  }
  if (auto v = r.choice("direction", {"forward", "reverse", "bidirectional"}))
    m.direction = static_cast<Direction>(*v);
  if (r.has("reverse_every") && m.direction != Direction::Bidirectional)
    r.fail("reverse_every", "no reverse_every unless mill.direction = \"bidirectional\"");
  if (auto v = r.number("reverse_every", open_closed(0.0, kMaxHours), "hours of operation"))
    m.reverse_every_hours = *v;
}

void read_lifters(const TableReader& r, Scene& s, const std::string& file) {
  if (!r.has("rows")) r.missing("rows", "an integer in [1, 1000] (lifter rows)");
  s.mill.rows = static_cast<int>(*r.integer("rows", 1, 1000, "lifter rows"));
  // 0.1 mm: finer than any particle the solver can take; the liner's edge count is bounded
  // again once the lifter is known (scene/limits.hpp).
  if (auto v = r.number("shell_edge", closed(0.1, 10000.0), "mm, target edge length on the shell"))
    s.mill.mesh.shell_edge_m = *v * kMm;
  if (auto v = r.number("lifter_edge", closed(0.1, 10000.0), "mm, target edge length on the lifters"))
    s.mill.mesh.lifter_edge_m = *v * kMm;

  // A worn liner measured at a known time: the history's clock starts there.
  if (auto v = r.number("start_hours", closed(0.0, kMaxHours), "operating hours of the liner the history starts from"))
    s.wear.start_hours = *v;

  exactly_one(r, "profile", "pattern", "one profile for every row, or a pattern of profiles");
  auto load = [&](const std::string& rel, const std::string& key, const toml::node& at) {
    if (rel.empty()) throw InputError(file, key, "expected a profile file name" + line_text(at));
    const fs::path resolved = (fs::path(file).parent_path() / fs::path(rel)).lexically_normal();
    std::error_code ec;
    if (!fs::is_regular_file(resolved, ec))
      throw InputError(file, key, "expected an existing profile file; tried '" + resolved.string() + "'" + line_text(at));
    try {
      return load_profile(resolved.string());  // its errors name the profile file ...
    } catch (const InputError& e) {
      // ... and the scene key that named it (a scene given where a profile belongs, say).
      const auto line = at.source().begin.line;
      throw InputError(e.file, e.where,
                       e.expected + " (the profile named by " + key + " in " + file +
                           (line > 0 ? ", line " + std::to_string(line) : std::string()) + ")");
    }
  };
  if (r.has("profile")) {
    const auto rel = r.string("profile");
    s.mill.lifter = load(*rel, "lifters.profile", *r.raw().get("profile"));
    return;
  }
  const toml::node& node = *r.raw().get("pattern");
  const toml::array* arr = node.as_array();
  // 64 kinds: far more than any liner pattern (hi-lo is 2, hi-mid-lo 3).
  if (!arr || arr->empty() || arr->size() > 64)
    throw InputError(file, "lifters.pattern",
                     "expected an array of 1 to 64 profile files, e.g. [\"hi.toml\", \"lo.toml\"]" + line_text(node));
  for (std::size_t k = 0; k < arr->size(); ++k) {
    const toml::node& e = *arr->get(k);
    const std::string key = "lifters.pattern[" + std::to_string(k) + "]";
    if (!e.is_string()) throw InputError(file, key, "expected a profile file name (a string), " + got_text(e) + line_text(e));
    s.mill.pattern.push_back(load(*e.value<std::string>(), key, e));
    // A kind is known by its profile's name in every output (kinds.csv, summary.csv's
    // kindK_profile, the figure's titles, the manifest). The same profile twice is one kind
    // repeated (a plain liner as a pattern), but two profiles of other shapes under one name
    // would read as one: refused, naming both keys.
    const LifterProfile& added = s.mill.pattern.back();
    for (std::size_t j = 0; j < k; ++j) {
      const LifterProfile& earlier = s.mill.pattern[j];
      if (earlier.name != added.name) continue;
      if (earlier.points == added.points && earlier.measured == added.measured) continue;
      throw InputError(file, key,
                       "expected kinds of other shapes to have other names: the profile named '" + added.name +
                           "' here is of other points than the one of that name in lifters.pattern[" +
                           std::to_string(j) + "] (" +
                           (added.measured.empty() ? std::string("give one of the profiles another `name`")
                                                   : std::string("a scan is named by its file: rename one of the "
                                                                 "files")) +
                           ")" + line_text(e));
    }
  }
  if (s.mill.rows % static_cast<int>(arr->size()) != 0)
    r.fail("rows", "a multiple of the pattern's " + std::to_string(arr->size()) +
                       " kinds, so the pattern repeats evenly around the mill");
  s.mill.lifter = s.mill.pattern.front();
}

SpeciesDef read_species(const TableReader& r) {
  SpeciesDef sp;
  if (auto v = r.string("name")) sp.name = *v;
  else r.missing("name", "a species name (e.g. \"rock\", \"ball\")");
  // Species names are written into snapshot files.
  if (!is_safe_name(sp.name)) r.fail("name", safe_name_rule());
  if (auto v = r.boolean("ball")) sp.is_ball = *v;
  // 100 kg/m^3: lighter than any ore or grinding medium (cork is 120); 25000: denser than
  // any metal used for grinding.
  sp.density_kg_m3 = r.need_number("density", closed(100.0, 25000.0), "kg/m^3");

  if (r.has("sizes") && r.has("size_range"))
    r.fail("size_range", "only one of 'sizes' (with mass_fractions) and 'size_range'");
  if (!r.has("sizes") && !r.has("size_range"))
    r.missing("sizes", "'sizes' (mm, with 'mass_fractions') or 'size_range' = [min, max] (mm)");
  if (!r.has("distribution"))
    for (const char* key : {"top_size", "size_63", "exponent"})
      if (r.has(key)) r.fail(key, "only with 'distribution' (gates-gaudin-schuhmann or rosin-rammler)");
  // 0.1 mm: fine rock; below it a charge would hold far more disks than any run can take.
  if (auto sizes = r.numbers("sizes", closed(0.1, 20000.0), "mm, diameters", 1)) {
    for (double d : *sizes) sp.diameters_m.push_back(d * kMm);
    if (r.has("distribution")) {
      // A size distribution's form gives the fractions (filling.hpp).
      if (r.has("mass_fractions"))
        r.fail("mass_fractions", "only one of 'mass_fractions' and 'distribution'");
      const auto form = *r.choice("distribution", {"gates-gaudin-schuhmann", "rosin-rammler"});
      const bool ggs = form == 0;
      const char* scale_key = ggs ? "top_size" : "size_63";
      const char* other_key = ggs ? "size_63" : "top_size";
      if (r.has(other_key))
        r.fail(other_key, std::string("'") + scale_key + "' with distribution = \"" +
                              (ggs ? "gates-gaudin-schuhmann" : "rosin-rammler") + "\"");
      const double scale_mm = r.need_number(scale_key, closed(0.1, 20000.0),
                                            ggs ? "mm, the size all rock passes" : "mm, 63.2% passing");
      // 0.1-5: measured mill feeds and products lie within 0.5-1.5 (both forms).
      const double exponent = r.need_number("exponent", closed(0.1, 5.0), "distribution modulus");
      double largest = 0.0;
      for (double d : *sizes) largest = std::max(largest, d);
      if (ggs && largest > scale_mm)
        r.fail("top_size", "a top size at least the largest of 'sizes' (" + num_text(largest) + " mm)");
      for (std::size_t i = 0; i < sizes->size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
          if ((*sizes)[i] == (*sizes)[j]) r.fail("sizes", "distinct sizes with 'distribution'");
      sp.mass_fractions = distribution_mass_fractions(
          ggs ? SizeForm::GatesGaudinSchuhmann : SizeForm::RosinRammler, sp.diameters_m, scale_mm * kMm, exponent,
          &sp.distribution_held, &sp.distribution_coarse);
      // The classes hold the mass from the smallest size up (filling.hpp); all of it finer (or,
      // for one class at the top size, none above it) leaves them none.
      double smallest = largest;
      for (double d : *sizes) smallest = std::min(smallest, d);
      for (double f : sp.mass_fractions)
        if (!std::isfinite(f))
          r.fail(scale_key, std::string("a distribution with some of its mass from the smallest of 'sizes' (") +
                                num_text(smallest) + " mm) up, which the classes hold; with " + scale_key + " = " +
                                num_text(scale_mm) + " mm and exponent " + num_text(exponent) +
                                " none lies there: list smaller sizes" + (ggs ? "" : " or give a larger size_63"));
    } else if (auto f = r.numbers("mass_fractions", closed(0.0, 1.0), "", 1)) {
      if (f->size() != sizes->size())
        r.fail("mass_fractions", "one fraction per size (" + std::to_string(sizes->size()) + ")");
      double sum = 0.0;
      for (double x : *f) sum += x;
      // 1e-6: fractions typed with six decimals must pass; anything looser is a typo.
      if (std::abs(sum - 1.0) > 1e-6)
        r.fail("mass_fractions", "fractions summing to 1 within 1e-6 (sum is " + num_text(sum) + ")");
      sp.mass_fractions = *f;
    } else if (sizes->size() == 1) {
      sp.mass_fractions = {1.0};
    } else {
      r.missing("mass_fractions", "one mass fraction per size, summing to 1");
    }
  } else {
    if (r.has("mass_fractions"))
      r.fail("mass_fractions", "no mass_fractions with size_range (they go with 'sizes')");
    if (r.has("distribution"))
      r.fail("distribution", "a distribution with 'sizes' (its classes), not with 'size_range'");
    const auto range = *r.numbers("size_range", closed(0.1, 20000.0), "mm, diameters", 2);
    if (range.size() != 2 || !(range[0] < range[1]))
      r.fail("size_range", "[min, max] with 0 < min < max (mm)");
    sp.d_min_m = range[0] * kMm;
    sp.d_max_m = range[1] * kMm;
  }
  if (auto v = r.number("friction", closed(0.0, 2.0), "")) sp.friction = *v;
  if (auto v = r.number("restitution", closed(0.0, 1.0), "")) sp.restitution = *v;
  if (auto v = r.number("friction_liner", closed(0.0, 2.0), "")) sp.friction_liner = *v;
  if (auto v = r.number("restitution_liner", closed(0.0, 1.0), "")) sp.restitution_liner = *v;
  if (auto v = r.number("rolling_resistance", closed(0.0, 1.0), "times radius = lever arm"))
    sp.rolling_resistance = *v;
  return sp;
}

void read_charge(const TableReader& r, Scene& s, const std::string& file) {
  ChargeDef& c = s.charge;
  c.filling = r.need_number("filling", open(0.0, 0.6), "fraction of the mill area");
  c.ball_filling = r.need_number("ball_filling", closed(0.0, c.filling),
                                 "fraction of the mill area, at most charge.filling");
  // A settled bed of disks of mixed sizes packs near 0.8; hexagonal packing (0.9069) is
  // the most any 2D disk bed can reach.
  if (auto v = r.number("bulk_packing", open_closed(0.0, 0.9069), "solid area fraction"))
    c.bulk_packing = *v;

  const toml::array* arr = r.array("species");
  if (!arr || arr->empty())
    r.missing("species", "at least one [[charge.species]] table");
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const std::string prefix = "charge.species[" + std::to_string(i) + "]";
    const toml::node& n = (*arr)[i];
    if (!n.is_table())
      throw InputError(file, prefix, "expected a table [[charge.species]], " + got_text(n) + line_text(n));
    TableReader sr(*n.as_table(), prefix, file, &s.explicit_keys,
                   {"name", "ball", "density", "sizes", "mass_fractions", "size_range", "distribution",
                    "top_size", "size_63", "exponent", "friction", "restitution", "friction_liner",
                    "restitution_liner", "rolling_resistance"});
    c.species.push_back(read_species(sr));
    for (std::size_t j = 0; j + 1 < c.species.size(); ++j)
      if (c.species[j].name == c.species.back().name)
        sr.fail("name", "a name not used by charge.species[" + std::to_string(j) + "]");
  }
  const bool any_ball = std::any_of(c.species.begin(), c.species.end(),
                                    [](const SpeciesDef& sp) { return sp.is_ball; });
  const bool any_rock = std::any_of(c.species.begin(), c.species.end(),
                                    [](const SpeciesDef& sp) { return !sp.is_ball; });
  if (c.ball_filling > 0.0 && !any_ball)
    throw InputError(file, "charge.species",
                     "expected a species with ball = true, since charge.ball_filling = " +
                         num_text(c.ball_filling) + " > 0" + line_text(*arr));
  if (c.filling > c.ball_filling && !any_rock)
    throw InputError(file, "charge.species",
                     "expected a species with ball = false (rock), since charge.filling > charge.ball_filling" +
                         line_text(*arr));
}

void read_solver(const TableReader& r, Scene& s) {
  SolverDef& v = s.solver;
  if (auto b = r.choice("backend", {"box2d", "soft"})) v.backend = static_cast<Backend>(*b);
  if (r.has("time_step") && r.has("steps_per_second"))
    r.fail("steps_per_second", "only one of 'solver.time_step' and 'solver.steps_per_second'");
  // 0.05 s: beyond it a disk falls more than its own size per step under gravity alone.
  // 1e-6 s: a microsecond step is finer than any DEM of a mill needs.
  if (auto x = r.number("time_step", closed(1e-6, 0.05), "s")) v.time_step_s = *x;
  if (auto x = r.number("steps_per_second", closed(20.0, 1e6), "steps per simulated s"))
    v.time_step_s = 1.0 / *x;
  if (auto x = r.integer("velocity_iterations", 1, 1000)) v.velocity_iterations = static_cast<int>(*x);
  if (auto x = r.integer("position_iterations", 1, 1000)) v.position_iterations = static_cast<int>(*x);
  if (auto x = r.integer("substeps", 1, 1000)) v.substeps = static_cast<int>(*x);
  if (auto x = r.number("contact_hertz", closed(0.0, 1e7), "Hz; 0: substeps / time_step / 8"))
    v.contact_hertz = *x;
  if (auto x = r.number("damping_ratio", open_closed(0.0, 1e4), "contact damping ratio")) v.damping_ratio = *x;
  if (auto x = r.number("push_out", open_closed(0.0, 1e6), "smallest particle radii per second"))
    v.push_out_radii_per_s = *x;
  if (auto x = r.number("settle_time", closed(0.0, 1000.0), "s")) v.settle_time_s = *x;
  if (auto x = r.number("spinup_revolutions", closed(0.0, 1000.0), "revolutions")) v.spinup_revolutions = *x;
  if (auto x = r.integer("seed", 0, std::numeric_limits<long long>::max()))
    v.seed = static_cast<std::uint64_t>(*x);
  if (auto x = r.number("size_cutoff", closed(0.0, 20000.0), "mm; rock sizes below are left out"))
    v.size_cutoff_m = *x * kMm;
}

void read_run(const TableReader& r, Scene& s) {
  if (auto x = r.number("revolutions", open_closed(0.0, kMaxRevolutions), "measured revolutions"))
    s.run.revolutions = *x;
}

void read_wear(const TableReader& r, Scene& s) {
  WearDef& w = s.wear;
  if (auto m = r.choice("mode", {"staged", "continuous"})) w.mode = static_cast<WearMode>(*m);
  const int given = int(r.has("wear_rate")) + int(r.has("area_loss_rate")) + int(r.has("height_loss_rate"));
  if (given != 1) {
    const std::string what =
        "exactly one of 'wear.wear_rate' (m^3/J), 'wear.area_loss_rate' (mm^2 per 1000 h) or "
        "'wear.height_loss_rate' (mm/h)";
    if (given == 0) r.missing("wear_rate", what);
    r.fail(r.has("height_loss_rate") ? "height_loss_rate" : "area_loss_rate", what);
  }
  // 1e-6 m^3/J: a million times any measured Archard rate of mill liners (1e-18 to 1e-12);
  // 1e-20: a hundredth of the smallest.
  if (auto x = r.number("wear_rate", closed(1e-20, 1e-6), "m^3/J, Archard C = K/H")) {
    w.rate_source = WearRateSource::Given;
    w.wear_rate_m3_per_J = *x;
  }
  // Shell plates of their own material; bounds as for wear_rate.
  if (auto x = r.number("shell_wear_rate", closed(1e-20, 1e-6), "m^3/J, Archard C of the shell plates"))
    w.shell_wear_rate_m3_per_J = *x;
  if (auto x = r.number("area_loss_rate", open_closed(0.0, 1e9), "mm^2 of lifter area per 1000 h, new lifter")) {
    w.rate_source = WearRateSource::AreaLossRate;
    w.calibration_value = *x;
    w.target_loss_rate = *x * 1e-6 / (1000.0 * kSecondsPerHour);
    w.wear_rate_m3_per_J = 0.0;  // the wear module calibrates C from it
  }
  if (auto x = r.number("height_loss_rate", open_closed(0.0, 1000.0), "mm of lifter height per h, new lifter")) {
    w.rate_source = WearRateSource::HeightLossRate;
    w.calibration_value = *x;
    w.target_loss_rate = *x * 1e-3 / kSecondsPerHour;
    w.wear_rate_m3_per_J = 0.0;
  }
  // 1e12: a whole liner life (1e4 h) in under a tenth of a simulated second; any larger
  // wears a lifter away within one window.
  if (auto x = r.number("factor", open_closed(0.0, 1e12), "C_model = factor * C")) w.factor = *x;
  // A stage of at least an hour: shorter ones wear less than one re-smoothing moves the surface.
  if (auto x = r.number("stage_hours", closed(kMinStageHours, kMaxHours), "hours of operation")) w.stage_hours = *x;
  if (auto x = r.integer("stages", 1, kMaxStages)) w.stages = static_cast<int>(*x);
  if (auto x = r.number("window_revolutions", open_closed(0.0, kMaxRevolutions), "revolutions"))
    w.window_revolutions = *x;
  if (auto x = r.number("max_depth_step", open_closed(0.0, 1000.0), "mm")) w.max_depth_step_m = *x * kMm;
  if (auto x = r.number("update_interval", open_closed(0.0, 1000.0), "s of simulated time"))
    w.update_interval_s = *x;
  // Below a hundredth of a millimetre the re-smoothing works at the scale of rounding errors
  // and a worn liner unit can vanish in it.
  if (auto x = r.number("smoothing_radius", closed(0.0, 1000.0), "mm; 0 = smallest particle radius")) {
    if (*x > 0.0 && *x < 0.01) r.fail("smoothing_radius", "0 (the smallest particle radius) or 0.01 to 1000 mm");
    w.smoothing_radius_m = *x * kMm;
  }
  if (auto x = r.boolean("average_rows")) w.average_rows = *x;
  if (auto x = r.boolean("shell_wear")) w.shell_wear = *x;
  if (auto x = r.boolean("packed_wear")) w.packed_wear = *x;
  if (auto x = r.number("replacement_height", closed(0.0, 10000.0), "mm")) w.replacement_height_m = *x * kMm;
  if (auto x = r.number("liner_density", closed(100.0, 25000.0), "kg/m^3")) w.liner_density_kg_m3 = *x;
  if (auto x = r.number("target_uncertainty", {0.0, 1.0, false, true}, "relative; 0 = off"))
    w.target_rel_uncertainty = *x;
}

void read_outputs(const TableReader& r, Scene& s) {
  if (auto x = r.boolean("collision_spectrum")) s.outputs.collision_spectrum = *x;
  if (auto x = r.boolean("shell_work")) s.outputs.shell_work = *x;
  if (auto x = r.boolean("snapshot")) s.outputs.snapshot = *x;
  if (auto x = r.boolean("contact_log")) s.outputs.contact_log = *x;
  if (auto x = r.boolean("vtk")) s.outputs.vtk = *x;
  // 1000 frames of a thousand disks is tens of megabytes per stage: more is a typo.
  if (auto x = r.integer("vtk_frames", 1, 1000, "frames per measuring window")) s.outputs.vtk_frames = static_cast<int>(*x);
}

// Checks across sections, once everything is read (profile loaded, preset applied).
void check_across_sections(const Scene& s, const std::string& file) {
  const double R = s.radius_m();
  if (s.wear.shell_wear_rate_m3_per_J > 0.0 && !s.wear.shell_wear)
    throw InputError(file, "wear.shell_wear_rate", "no shell_wear_rate with wear.shell_wear = false");
  for (int kind = 0; kind < s.mill.kind_count(); ++kind) {
  const LifterProfile& prof = s.mill.kind(kind);
  // The key that names this kind's profile, and the profile's name.
  const std::string key = s.mill.profile_key(kind);
  const std::string named = "profile '" + prof.name + "'";
  const auto& pts = prof.points;
  if (!pts.empty()) {
    double xmin = kInf, xmax = -kInf, ymax = 0.0;
    for (const Vec2& p : pts) {
      xmin = std::min(xmin, p.x), xmax = std::max(xmax, p.x);
      ymax = std::max(ymax, p.y);
    }
    // The lifter bases must not touch: base width < pitch (arc between rows at the shell).
    const double pitch = 2.0 * kPi * R / s.mill.rows;
    const double rows_that_fit = std::floor(2.0 * kPi * R / (xmax - xmin) - 1e-9);
    if (!(rows_that_fit >= 1.0))
      throw InputError(file, key,
                       "expected a lifter narrower than the shell's circumference (" +
                           num_text(2.0 * kPi * R / kMm) + " mm); " + named + " is " +
                           num_text((xmax - xmin) / kMm) + " mm wide at its widest");
    if (xmax - xmin >= pitch) {
      // A pattern's rows are a whole number of its repeats.
      const double repeat = static_cast<double>(s.mill.kind_count());
      const double most = std::floor(std::min(rows_that_fit, 1e9) / repeat) * repeat;
      throw InputError(file, "lifters.rows",
                       "expected at most " + std::to_string(static_cast<long long>(most)) + " rows" +
                           (repeat > 1.0 ? " (a multiple of the pattern's " + num_text(repeat) + " kinds)" : "") +
                           ": the width of " + named + " (" + num_text((xmax - xmin) / kMm) +
                           " mm at its widest) must be under the pitch (" + num_text(pitch / kMm) + " mm)");
    }
    // Lifters reaching past half the radius leave no room for a charge at any filling.
    if (ymax >= 0.5 * R)
      throw InputError(file, key,
                       "expected a lifter lower than half the mill radius (" + num_text(0.5 * R / kMm) +
                           " mm); " + named + " is " + num_text(ymax / kMm) + " mm high");
    // A measured surface's shell plates lie a plate's thickness below the shell line at most:
    // a tenth of the radius is far past any liner (a typo, or metres for millimetres).
    double ymin = 0.0;
    for (const Vec2& p : prof.measured) ymin = std::min(ymin, p.y);
    if (ymin < -0.1 * R)
      throw InputError(prof.source_file.empty() ? file : prof.source_file, "x_mm,y_mm",
                       "expected a measured surface within a tenth of the mill radius (" + num_text(0.1 * R / kMm) +
                           " mm) below the shell line, y = 0; " + named + " reaches y = " + num_text(ymin / kMm) +
                           " mm (" + file + ", " + key + ")");
    if (s.wear.replacement_height_m >= ymax)
      throw InputError(file, "wear.replacement_height",
                       "expected a height below the new lifter's (" + num_text(ymax / kMm) + " mm), got " +
                           num_text(s.wear.replacement_height_m / kMm) + " mm");
    // A measured surface must fit the pitch as a whole (its shell plates too).
    if (!s.mill.kind(kind).measured.empty()) new_liner_unit(s, kind);
  }
  }
  // Twelve digits: a cut-off refused as above the largest size (by more than a billionth of
  // it) must not print as equal to it.
  const auto digits12 = [](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.12g", v);
    return std::string(buf);
  };
  for (std::size_t i = 0; i < s.charge.species.size(); ++i) {
    const SpeciesDef& sp = s.charge.species[i];
    const std::string key = "charge.species[" + std::to_string(i) + "]";
    // A particle a quarter of the mill across cannot tumble; it is a typo (m for mm).
    if (sp.largest_diameter_m() >= 0.25 * s.mill.diameter_m)
      throw InputError(file, key + (sp.diameters_m.empty() ? ".size_range" : ".sizes"),
                       "expected particles smaller than a quarter of the mill diameter (" +
                           num_text(0.25 * s.mill.diameter_m / kMm) + " mm)");
    // The cut-off must keep a class with mass (largest_diameter_m: the largest that has some;
    // the fractions of the classes kept are what the cut-off renormalises).
    if (!sp.is_ball && s.solver.size_cutoff_m > 0.0 && !SpeciesDef::size_kept(sp.largest_diameter_m(), s.solver.size_cutoff_m))
      throw InputError(file, "solver.size_cutoff",
                       "expected a cut-off that keeps some of the mass of " + key + " ('" + sp.name +
                           "', largest size with mass " + digits12(sp.largest_diameter_m() / kMm) + " mm), got " +
                           digits12(s.solver.size_cutoff_m / kMm) + " mm");
  }
}

// ---------------------------------------------------------------------------------------
// Command-line overrides (--set KEY=VALUE)
// ---------------------------------------------------------------------------------------

// One part of a dotted key: a name and, for an array of tables, an index ("species[1]").
struct KeyPart {
  std::string name;
  std::optional<std::size_t> index;
};

std::string set_where(const std::string& text) { return "--set " + printable(text, 80); }

std::vector<KeyPart> split_key(const std::string& key, const std::string& text) {
  const auto bad = [&](const std::string& why) -> InputError {
    return InputError("", set_where(text),
                      "expected KEY=VALUE with KEY a dotted scene key (e.g. mill.speed, "
                      "charge.species[1].density); " + why);
  };
  std::vector<KeyPart> parts;
  std::size_t i = 0;
  while (true) {
    KeyPart p;
    while (i < key.size() && (std::isalnum(static_cast<unsigned char>(key[i])) || key[i] == '_' || key[i] == '-'))
      p.name += key[i++];
    if (p.name.empty()) throw bad("an empty or malformed part in '" + printable_key(key) + "'");
    if (i < key.size() && key[i] == '[') {
      std::size_t close = key.find(']', i);
      const std::string digits = close == std::string::npos ? "" : key.substr(i + 1, close - i - 1);
      if (digits.empty() || digits.size() > 6 ||
          !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
        throw bad("an index is [0], [1], ...");
      p.index = static_cast<std::size_t>(std::stoul(digits));
      i = close + 1;
    }
    parts.push_back(std::move(p));
    if (i == key.size()) break;
    if (key[i] != '.') throw bad("unexpected '" + printable(key.substr(i, 1), 4) + "' in '" + printable_key(key) + "'");
    ++i;
  }
  return parts;
}

// A copy of a parsed value without its source position: messages about it must not point
// at "line 1" of a file it never was in. Into table `t` under `key`, or onto array `a`.
void copy_value(const toml::node& n, toml::table* t, const std::string& key, toml::array* a) {
  const auto put = [&](auto&& v) {
    if (t) t->insert(key, std::move(v));
    else a->push_back(std::move(v));
  };
  switch (n.type()) {
    case toml::node_type::table: {
      toml::table c;
      for (const auto& [k, v] : *n.as_table()) copy_value(v, &c, std::string(k.str()), nullptr);
      put(std::move(c));
      break;
    }
    case toml::node_type::array: {
      toml::array c;
      for (const auto& v : *n.as_array()) copy_value(v, nullptr, "", &c);
      put(std::move(c));
      break;
    }
    case toml::node_type::string: put(std::string(n.as_string()->get())); break;
    case toml::node_type::integer: put(n.as_integer()->get()); break;
    case toml::node_type::floating_point: put(n.as_floating_point()->get()); break;
    case toml::node_type::boolean: put(n.as_boolean()->get()); break;
    case toml::node_type::date: put(n.as_date()->get()); break;
    case toml::node_type::time: put(n.as_time()->get()); break;
    case toml::node_type::date_time: put(n.as_date_time()->get()); break;
    default: break;
  }
}

// The value as TOML ("0.8", "true", "[1, 2]", "\"text\""), or the text itself as a string
// when it is not a TOML value (a bare word: "reverse", "draft"), under the key "v".
toml::table value_holder(const std::string& value, const std::string& where) {
  toml::table out;
  try {
    const toml::table t = toml::parse("v = " + value);
    if (t.size() == 1 && t.contains("v")) {
      copy_value(*t.get("v"), &out, "v", nullptr);
      return out;
    }
  } catch (const toml::parse_error& e) {
    // A number TOML cannot hold (1e400) or does not write so (.8, an integer past 64 bits) is
    // not a word: taken as a string, its key's error would say "got a string".
    const char* begin = value.c_str();
    char* end = nullptr;
    const double v = std::strtod(begin, &end);
    if (end != begin && *end == '\0') {
      if (!std::isfinite(v))
        throw InputError("", where, "expected a number within a double's range (about 1.8e308), got " + value);
      throw InputError("", where,
                       "expected a number as TOML writes one (0.8 rather than .8; a whole number up to "
                       "9.2e18, or with a decimal point beyond), got " + value + " (TOML: " +
                           std::string(e.description()) + ")");
    }
  }
  out.insert("v", value);
  return out;
}

// Keys of which a table takes one: setting one from the command line replaces the file's.
const std::vector<std::vector<std::string>>& alternatives(const std::string& table) {
  static const std::map<std::string, std::vector<std::vector<std::string>>> groups{
      {"mill", {{"speed", "speed_rpm"}}},
      {"solver", {{"time_step", "steps_per_second"}}},
      {"wear", {{"wear_rate", "area_loss_rate", "height_loss_rate"}}},
      // A species takes discrete sizes or a range; discrete sizes take fractions or a
      // distribution, and a distribution its form's keys.
      {"charge.species",
       {{"sizes", "size_range"},
        {"mass_fractions", "size_range"},
        {"distribution", "size_range"},
        {"top_size", "size_range"},
        {"size_63", "size_range"},
        {"exponent", "size_range"},
        {"distribution", "mass_fractions"},
        {"top_size", "mass_fractions"},
        {"size_63", "mass_fractions"},
        {"exponent", "mass_fractions"}}},
  };
  static const std::vector<std::vector<std::string>> none;
  const auto it = groups.find(table);
  return it == groups.end() ? none : it->second;
}

// The keys of table `plain` (dotted, without indexes) that setting its key `name` to `value`
// removes: the other keys of its alternatives, a one-way mill's reverse_every, the other
// distribution form's scale.
std::vector<std::string> keys_removed_by(const std::string& plain, const std::string& name, const std::string& value) {
  std::vector<std::string> out;
  for (const auto& group : alternatives(plain))
    if (std::find(group.begin(), group.end(), name) != group.end())
      for (const auto& other : group)
        if (other != name) out.push_back(other);
  // reverse_every belongs to a bidirectional mill only: a one-way direction drops it.
  if (plain == "mill" && name == "direction" && value != "bidirectional" && value != "\"bidirectional\"")
    out.push_back("reverse_every");
  // A distribution's form has its own scale: the other form's goes.
  if (plain == "charge.species" && name == "distribution") {
    std::string form = value;
    if (form.size() >= 2 && (form.front() == '"' || form.front() == '\'') && form.back() == form.front())
      form = form.substr(1, form.size() - 2);
    if (form == "rosin-rammler") out.push_back("top_size");
    if (form == "gates-gaudin-schuhmann") out.push_back("size_63");
  }
  return out;
}

struct OverrideText {
  std::string key;
  std::string value;
};

OverrideText split_override(const std::string& text) {
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("", set_where(text), "expected KEY=VALUE, e.g. --set mill.speed=0.8");
  OverrideText o{text.substr(0, eq), text.substr(eq + 1)};
  while (!o.key.empty() && o.key.back() == ' ') o.key.pop_back();
  while (!o.value.empty() && o.value.front() == ' ') o.value.erase(o.value.begin());
  return o;
}

void apply_override(toml::table& root, const std::string& text) {
  const OverrideText o = split_override(text);
  const std::string& value = o.value;
  const std::vector<KeyPart> parts = split_key(o.key, text);

  toml::table* table = &root;
  std::string path;    // dotted, with indexes: for messages
  std::string plain;   // dotted, without indexes: which alternatives apply
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const KeyPart& p = parts[k];
    const bool last = k + 1 == parts.size();
    const std::string here = path.empty() ? p.name : path + "." + p.name;
    if (last && !p.index) {
      for (const std::string& other : keys_removed_by(plain, p.name, value)) table->erase(other);
      toml::table holder = value_holder(value, set_where(text) + ": " + here);
      table->insert_or_assign(p.name, std::move(*holder.get("v")));
      return;
    }
    toml::node* child = table->get(p.name);
    if (!child) {
      if (p.index)
        throw InputError("", set_where(text), "expected an existing array of tables '" + here + "' to index");
      child = &table->insert(p.name, toml::table{}).first->second;
    }
    if (p.index) {
      toml::array* arr = child->as_array();
      if (!arr)
        throw InputError("", set_where(text), "expected '" + here + "' to be an array of tables, " + got_text(*child));
      if (*p.index >= arr->size())
        throw InputError("", set_where(text), "expected an index below " + std::to_string(arr->size()) + " for '" +
                                                  here + "' (it has " + std::to_string(arr->size()) + ")");
      child = arr->get(*p.index);
      if (last) {
        toml::table holder = value_holder(value, set_where(text) + ": " + here + "[" + std::to_string(*p.index) + "]");
        arr->replace(arr->cbegin() + static_cast<std::ptrdiff_t>(*p.index), std::move(*holder.get("v")));
        return;
      }
    }
    if (!child->is_table())
      throw InputError("", set_where(text), "expected '" + here + (p.index ? "[" + std::to_string(*p.index) + "]" : "") +
                                                "' to be a table, " + got_text(*child));
    table = child->as_table();
    path = here + (p.index ? "[" + std::to_string(*p.index) + "]" : "");
    plain = plain.empty() ? p.name : plain + "." + p.name;
  }
}

// The override a reader's error comes from, if any: the error's key is the overridden key,
// inside it, or a table on its way ("foo" for foo.bar=1).
const std::string* override_of(const std::vector<std::string>& overrides, const std::string& where) {
  if (where.empty()) return nullptr;
  for (auto it = overrides.rbegin(); it != overrides.rend(); ++it) {
    std::string key = it->substr(0, it->find('='));
    while (!key.empty() && key.back() == ' ') key.pop_back();
    const auto within = [](const std::string& inner, const std::string& outer) {
      return inner.size() > outer.size() && inner.compare(0, outer.size(), outer) == 0 &&
             (inner[outer.size()] == '.' || inner[outer.size()] == '[');
    };
    if (where == key || within(where, key) || within(key, where)) return &*it;
  }
  return nullptr;
}

InputError not_toml(const std::string& path, const toml::parse_error& e) {
  const auto& b = e.source().begin;
  return InputError(path, "line " + std::to_string(b.line),
                    "not valid TOML: " + std::string(e.description()) + " (column " + std::to_string(b.column) + ")");
}

// The scene from its parsed table (the file's, with the overrides in it).
Scene read_scene(const toml::table& root, const std::string& path) {
  // A comparison file names scenes; it is not one. Say so rather than call its table unknown.
  if (root.contains("comparison")) {
    std::string designs;
    if (const toml::array* a = root["comparison"]["designs"].as_array())
      for (const toml::node& d : *a)
        if (const auto v = d.value<std::string>()) designs += (designs.empty() ? "" : ", ") + *v;
    throw InputError(path, "comparison",
                     "a scene of one design; this file is a comparison of designs ([comparison]), which `millwear "
                     "run` and `millwear tradeoff` take. Give one of its designs' scenes" +
                         (designs.empty() ? std::string() : " (" + designs + ", beside it)"));
  }
  Scene s;
  s.source_file = path;
  s.name = safe_name_from(fs::path(path).stem().string());
  TableReader top(root, "", path, &s.explicit_keys,
                  {"name", "fidelity", "mill", "lifters", "charge", "solver", "run", "wear", "outputs"});
  if (auto v = top.string("name")) {
    // The name is part of output file names and CSV rows.
    if (!is_safe_name(*v)) top.fail("name", safe_name_rule());
    s.name = *v;
  }
  std::string fidelity = s.fidelity;
  const std::vector<std::string> fidelities = fidelity_names();
  if (auto v = top.choice("fidelity", fidelities)) fidelity = fidelities[static_cast<std::size_t>(*v)];

  auto section = [&](const char* key, bool required, std::vector<std::string> allowed) {
    const toml::table* t = top.table(key);
    if (!t && required) top.missing(key, std::string("a [") + key + "] table");
    return TableReader(t ? *t : kEmpty, key, path, &s.explicit_keys, std::move(allowed));
  };
  read_mill(section("mill", true,
                    {"diameter", "length", "slice_thickness", "speed", "speed_rpm", "direction",
                     "reverse_every"}),
            s);
  read_charge(section("charge", true, {"filling", "ball_filling", "bulk_packing", "species"}), s, path);
  read_solver(section("solver", false,
                      {"backend", "time_step", "steps_per_second", "velocity_iterations",
                       "position_iterations", "substeps", "contact_hertz", "damping_ratio", "push_out",
                       "settle_time", "spinup_revolutions", "seed",
                       "size_cutoff"}),
              s);
  read_run(section("run", false, {"revolutions"}), s);
  if (top.has("wear"))
    read_wear(section("wear", false,
                      {"mode", "wear_rate", "area_loss_rate", "height_loss_rate", "factor",
                       "stage_hours", "stages", "window_revolutions", "max_depth_step",
                       "update_interval", "smoothing_radius", "average_rows", "shell_wear", "shell_wear_rate",
                       "packed_wear", "replacement_height", "liner_density", "target_uncertainty"}),
              s);
  read_outputs(section("outputs", false, {"collision_spectrum", "shell_work", "snapshot", "contact_log", "vtk", "vtk_frames"}), s);
  // The profile last: every key of the scene is checked before another file is opened.
  read_lifters(section("lifters", true, {"rows", "profile", "pattern", "start_hours", "shell_edge", "lifter_edge"}),
               s, path);

  apply_fidelity(s, fidelity);
  check_across_sections(s, path);
  return s;
}

// The file's table with the overrides put in; errors name the file.
toml::table overridden_table(const std::string& path, const std::vector<std::string>& overrides) {
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    throw not_toml(path, e);
  }
  for (const std::string& text : overrides) {
    try {
      apply_override(root, text);
    } catch (const InputError& e) {
      throw InputError(path, e.where, e.expected);
    }
  }
  return root;
}

}  // namespace

bool override_replaces(const std::string& later, const std::string& earlier) {
  std::vector<KeyPart> l, e;
  OverrideText lo;
  try {
    lo = split_override(later);
    l = split_key(lo.key, later);
    e = split_key(split_override(earlier).key, earlier);
  } catch (const InputError&) {
    return false;  // load_scene names a malformed override
  }
  const auto same = [](const KeyPart& a, const KeyPart& b) { return a.name == b.name && a.index == b.index; };
  std::size_t n = 0;
  while (n < l.size() && n < e.size() && same(l[n], e[n])) ++n;
  if (n == l.size()) return true;  // the same key, or a table or element that holds the earlier one
  if (n + 1 != l.size() || n + 1 != e.size() || l.back().index || e.back().index) return false;
  std::string plain;
  for (std::size_t k = 0; k < n; ++k) plain += (k ? "." : "") + l[k].name;
  const std::vector<std::string> removed = keys_removed_by(plain, l.back().name, lo.value);
  return std::find(removed.begin(), removed.end(), e.back().name) != removed.end();
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw InputError(path, "", "scene file not found or not a regular file");

  const toml::table root = overridden_table(path, overrides);
  try {
    Scene s = read_scene(root, path);
    s.overrides = overrides;
    return s;
  } catch (const InputError& e) {
    if (e.file != path || overrides.empty()) throw;
    // A problem with an overridden key is the command line's: say so.
    if (const std::string* from = override_of(overrides, e.where))
      throw InputError(path, "--set " + printable(*from, 80) + ": " + e.where, e.expected);
    // Another key's, which an override may have caused (a ball filling above the filling a
    // --set lowered): the overrides are named with it.
    std::string sets;
    for (const std::string& o : overrides) sets += " --set " + printable(o, 80);
    throw InputError(e.file, e.where, e.expected + " (the scene with" + sets + ")");
  }
}


std::string overridden_scene_toml(const std::string& path, const std::vector<std::string>& overrides) {
  std::ostringstream os;
  os << toml::toml_formatter{overridden_table(path, overrides)} << "\n";
  return os.str();
}

void check_derived_seeds(const Scene& scene, std::uint64_t count, const std::string& what) {
  constexpr auto kMaxSeed = static_cast<std::uint64_t>(std::numeric_limits<long long>::max());
  if (count == 0 || (scene.solver.seed <= kMaxSeed && count - 1 <= kMaxSeed - scene.solver.seed)) return;
  throw InputError(scene.source_file, "solver.seed",
                   "a seed s with s + " + std::to_string(count - 1) + " at most 2^63 - 1 (" + what + " uses seeds s .. s + " +
                       std::to_string(count - 1) + "), found " + std::to_string(scene.solver.seed));
}

Scene load_scene_text(const std::string& text, const std::string& path) {
  toml::table root;
  try {
    root = toml::parse(text, path);
  } catch (const toml::parse_error& e) {
    throw not_toml(path, e);
  }
  return read_scene(root, path);
}
}  // namespace millwear
