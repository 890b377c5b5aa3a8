// Screen files -> a validated ScreenDef; the family -> candidates -> candidate files.
//
// Candidates are checked by the code that will run them: each candidate's scene file is
// written and read back with load_scene and build_scene_mill, so a candidate is accepted
// exactly when `millwear run` would accept it (one code path, not a second set of rules).
#include "common/units.hpp"
#include "screen/screen.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <random>
#include <sstream>

#include <toml++/toml.h>

#include "common/errors.hpp"
#include "common/names.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/hash.hpp"
#include "io/run_folder.hpp"
#include "profiles/profile.hpp"
#include "scene/fidelity.hpp"
#include "scene/limits.hpp"
#include "scene/table_reader.hpp"
#include "wear/wear.hpp"

namespace millwear::screen {

namespace fs = std::filesystem;
namespace tr = toml_reader;

namespace {


// The most candidates a screen may have, drawn or on a grid.
constexpr int kMaxCandidates = 100000;

// A family parameter: a number, a list of numbers, or {min, max[, steps]}.
Axis read_axis(const tr::TableReader& r, const char* key, tr::Bounds b, const std::string& unit,
               const std::string& file, Sampling sampling, bool integer) {
  Axis a;
  const toml::node* n = r.raw().get(key);
  if (!n) return a;
  a.given = true;
  const std::string what = std::string(integer ? "an integer" : "a number") + " " + b.describe() +
                           " (" + unit + "), a list of them, or {min = , max = , steps = }";
  auto number = [&](const toml::node& e, const std::string& k) {
    const bool ok_type = integer ? e.is_integer() : e.is_number();
    double v = std::nan("");
    if (ok_type) v = e.is_integer() ? static_cast<double>(e.as_integer()->get()) : e.as_floating_point()->get();
    if (!ok_type || !std::isfinite(v) || !b.contains(v))
      throw InputError(file, k, "expected " + std::string(integer ? "an integer" : "a number") + " " +
                                    b.describe() + " (" + unit + "), " + tr::got_text(e) + tr::line_text(e));
    return v;
  };
  const std::string full = r.full(key);
  if (n->is_number()) {
    a.values.push_back(number(*n, full));
  } else if (n->is_array()) {
    const toml::array& arr = *n->as_array();
    if (arr.empty()) throw InputError(file, full, "expected " + what + ", got an empty list" + tr::line_text(*n));
    for (std::size_t i = 0; i < arr.size(); ++i) {
      const std::string k = full + "[" + std::to_string(i) + "]";
      const double v = number(arr[i], k);
      // A value twice makes the same candidates twice: twice the work for one design.
      for (std::size_t j = 0; j < a.values.size(); ++j)
        if (a.values[j] == v)
          throw InputError(file, k, "expected each value once, got " + io::format_exact(v) + " again (as " + full + "[" +
                                        std::to_string(j) + "])" + tr::line_text(arr[i]));
      a.values.push_back(v);
    }
  } else if (n->is_table()) {
    tr::TableReader t(*n->as_table(), full, file, nullptr, {"min", "max", "steps"});
    if (!t.has("min")) t.missing("min", "the range's lower end (" + unit + ")");
    if (!t.has("max")) t.missing("max", "the range's upper end (" + unit + ")");
    a.min = number(*t.raw().get("min"), full + ".min");
    a.max = number(*t.raw().get("max"), full + ".max");
    if (!(a.max > a.min)) t.fail("max", "a number greater than " + full + ".min");
    if (t.has("steps")) {
      const int steps = static_cast<int>(*t.integer("steps", 2, 10000, "values in the range"));
      for (int i = 0; i < steps; ++i) {
        double v = a.min + (a.max - a.min) * i / (steps - 1);
        if (integer) v = std::round(v);
        if (a.values.empty() || a.values.back() != v) a.values.push_back(v);
      }
    } else if (sampling == Sampling::Grid) {
      t.missing("steps", "an integer >= 2 (sampling = \"grid\" takes every value of the range)");
    } else if (integer) {
      for (double v = std::ceil(a.min); v <= a.max; v += 1.0) a.values.push_back(v);
    } else {
      a.is_range = true;
    }
  } else {
    r.fail(key, what);
  }
  return a;
}

std::string resolve(const std::string& file, const std::string& rel) {
  return (fs::path(file).parent_path() / fs::path(rel)).lexically_normal().string();
}

std::string fmt(double v) { return io::format_exact(v); }

// Entry k of a list of profile files (resolved against the screen file at `path`): it must
// name an existing file that loads as a profile (load_profile's errors name the file).
std::string listed_profile(const std::string& path, const toml::node& e, const std::string& k) {
  if (!e.is_string()) throw InputError(path, k, "expected a profile file name, " + tr::got_text(e) + tr::line_text(e));
  const std::string p = resolve(path, e.as_string()->get());
  std::error_code ec;
  if (!fs::is_regular_file(p, ec))
    throw InputError(path, k, "expected an existing profile file, relative to the screen file (tried '" + p + "')" +
                                  tr::line_text(e));
  load_profile(p);
  return p;
}

// The screen file as a TOML table; a file that is not TOML named with its line.
toml::table parse_screen_file(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) throw InputError(path, "", "screen file not found or not a regular file");
  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    const auto& b = e.source().begin;
    throw InputError(path, "line " + std::to_string(b.line),
                     "not valid TOML: " + std::string(e.description()) + " (column " + std::to_string(b.column) + ")");
  }
  return root;
}

// The [screen] table: the base scene, the history, the sampling, equal area and the power's sense.
void read_screen_table(const std::string& path, const tr::TableReader& s, ScreenDef& d) {
  std::error_code ec;
  if (auto v = s.string("name")) {
    if (!io::is_valid_design_name(*v)) s.fail("name", safe_name_rule());
    d.name = *v;
  }
  const auto base = s.string("base");
  if (!base) s.missing("base", "the base scene file, relative to the screen file");
  d.base_scene = resolve(path, *base);
  if (!fs::is_regular_file(d.base_scene, ec))
    s.fail("base", "an existing scene file, relative to the screen file (tried '" + d.base_scene + "')");
  const std::vector<std::string> fidelities = fidelity_names();
  if (auto v = s.choice("fidelity", fidelities)) d.fidelity = fidelities[static_cast<std::size_t>(*v)];
  if (auto v = s.integer("stages", 1, 10000)) d.stages = static_cast<int>(*v);
  if (auto v = s.number("stage_hours", tr::closed(kMinStageHours, kMaxHours), "hours of operation")) d.stage_hours = *v;
  if (auto v = s.choice("sampling", {"grid", "latin_hypercube"})) d.sampling = static_cast<Sampling>(*v);
  if (d.sampling == Sampling::LatinHypercube) {
    if (!s.has("samples")) s.missing("samples", "an integer in [1, " + std::to_string(kMaxCandidates) + "] (candidates to draw)");
    d.samples = static_cast<int>(*s.integer("samples", 1, kMaxCandidates, "candidates to draw"));
  } else if (s.has("samples")) {
    s.fail("samples", "no samples with sampling = \"grid\" (the grid takes every combination)");
  }
  if (auto v = s.integer("seed", 0, std::numeric_limits<long long>::max())) d.seed = static_cast<std::uint64_t>(*v);
  const toml::node* ea = s.raw().get("equal_area");
  if (ea && ea->is_array()) {
    const toml::array& arr = *ea->as_array();
    if (arr.empty()) s.fail("equal_area", "\"base\", a profile file, or a list of profile files (one per kind of lifter)");
    for (std::size_t i = 0; i < arr.size(); ++i)
      d.equal_area_kinds.push_back(listed_profile(path, arr[i], "screen.equal_area[" + std::to_string(i) + "]"));
    d.equal_area = "kinds";
  } else if (auto v = s.string("equal_area")) {
    if (*v == "base") {
      d.equal_area = "base";
    } else {
      d.equal_area = resolve(path, *v);
      if (!fs::is_regular_file(d.equal_area, ec))
        s.fail("equal_area", "\"base\" or an existing profile file, relative to the screen file (tried '" +
                                 d.equal_area + "')");
      load_profile(d.equal_area);  // its errors name the profile file
    }
  }
  if (auto v = s.choice("power", {"min", "max"})) d.power_higher_is_better = *v == 1;
}

// family.direction: "uni", "bi" or a list of them, each once.
void read_directions(const std::string& path, const tr::TableReader& f, ScreenDef& d) {
  const toml::node* n = f.raw().get("direction");
  auto word = [&](const toml::node& e, const std::string& k) {
    if (!e.is_string() || (e.as_string()->get() != "uni" && e.as_string()->get() != "bi"))
      throw InputError(path, k, "expected \"uni\" or \"bi\", " + tr::got_text(e) + tr::line_text(e));
    return e.as_string()->get();
  };
  if (n->is_array() && !n->as_array()->empty()) {
    for (std::size_t i = 0; i < n->as_array()->size(); ++i) {
      const std::string k = "family.direction[" + std::to_string(i) + "]";
      const std::string w = word((*n->as_array())[i], k);
      if (std::find(d.directions.begin(), d.directions.end(), w) != d.directions.end())
        throw InputError(path, k, "expected each direction once, got \"" + w + "\" again" +
                                      tr::line_text((*n->as_array())[i]));
      d.directions.push_back(w);
    }
  } else {
    d.directions.push_back(word(*n, "family.direction"));
  }
}

// family.profiles: the candidates are these files (no trapezoid keys, no equal area).
void read_family_profiles(const std::string& path, const tr::TableReader& f, const tr::TableReader& s,
                          ScreenDef& d) {
  for (const char* k : {"height", "top_width", "leading_face_angle", "trailing_face_angle", "symmetric"})
    if (f.has(k)) f.fail(k, "no trapezoid parameters with family.profiles (the profiles are the candidates)");
  if (!d.equal_area.empty())
    s.fail("equal_area", "no equal_area with family.profiles (it scales trapezoids only)");
  const toml::node* n = f.raw().get("profiles");
  if (!n->is_array() || n->as_array()->empty()) f.fail("profiles", "a list of profile files");
  for (std::size_t i = 0; i < n->as_array()->size(); ++i) {
    const std::string k = "family.profiles[" + std::to_string(i) + "]";
    const std::string p = listed_profile(path, (*n->as_array())[i], k);
    std::error_code ec;
    for (std::size_t j = 0; j < d.profiles.size(); ++j)
      if (fs::equivalent(d.profiles[j], p, ec))
        throw InputError(path, k, "expected each profile file once, got " + p + " again (as family.profiles[" +
                                      std::to_string(j) + "])" + tr::line_text((*n->as_array())[i]));
      else if (io::read_file(d.profiles[j]) == io::read_file(p))
        throw InputError(path, k, "expected each profile once, but " + p + " is a copy of " + d.profiles[j] +
                                      " (family.profiles[" + std::to_string(j) + "]): the same candidates twice" +
                                      tr::line_text((*n->as_array())[i]));
    d.profiles.push_back(p);
  }
}

// The [family] table: an axis per trapezoid parameter, rows and direction, or profile files.
void read_family_table(const std::string& path, const tr::TableReader& f, const tr::TableReader& s,
                       ScreenDef& d) {
  d.height_mm = read_axis(f, "height", tr::open_closed(0.0, 5000.0), "mm", path, d.sampling, false);
  d.top_width_mm = read_axis(f, "top_width", tr::open_closed(0.0, 5000.0), "mm", path, d.sampling, false);
  d.leading_deg = read_axis(f, "leading_face_angle", {0.0, 90.0, false, true}, "deg from radial", path, d.sampling, false);
  d.trailing_deg = read_axis(f, "trailing_face_angle", {0.0, 90.0, false, true}, "deg from radial", path, d.sampling, false);
  d.rows = read_axis(f, "rows", tr::closed(1, 1000), "lifter rows", path, d.sampling, true);
  if (auto v = f.boolean("symmetric")) d.symmetric = *v;
  if (d.symmetric && d.trailing_deg.given)
    f.fail("trailing_face_angle", "no trailing_face_angle with symmetric = true (it equals the leading one)");
  if (f.has("direction")) read_directions(path, f, d);
  if (f.has("profiles")) read_family_profiles(path, f, s, d);
  if (!d.equal_area.empty() && d.top_width_mm.given)
    f.fail("top_width", "no top_width with screen.equal_area (the area sets the top width)");
}

// A grid takes every combination: bound their count before any is made (each axis is bounded
// alone; their product is not). The same bound as screen.samples.
void check_grid_size(const std::string& path, const toml::table* ft, const ScreenDef& d) {
  double combinations = std::max<double>(1.0, double(d.profiles.size())) * std::max<double>(1.0, double(d.directions.size()));
  for (const Axis* a : {&d.height_mm, &d.top_width_mm, &d.leading_deg, &d.trailing_deg, &d.rows})
    if (a->given) combinations *= double(std::max<std::size_t>(1, a->values.size()));
  if (combinations > double(kMaxCandidates))
    throw InputError(path, "family",
                     "expected a grid of at most " + std::to_string(kMaxCandidates) +
                         " candidates (the product of the values of every family parameter), got " +
                         tr::num_text(combinations) + "; use fewer steps or sampling = \"latin_hypercube\"" +
                         (ft ? tr::line_text(*ft) : std::string()));
}

// --set overrides: keys the screen sets for every candidate itself are not the user's.
void check_overrides(const std::string& path, const std::vector<std::string>& overrides, const ScreenDef& d) {
  for (const std::string& o : overrides) {
    std::string key = o.substr(0, o.find('='));
    while (!key.empty() && key.back() == ' ') key.pop_back();
    const std::string plain = key.substr(0, key.find('['));
    std::string setter;
    if (plain == "name") setter = "the screen names every candidate (d000, d001, ...)";
    else if (plain == "lifters.profile" || plain == "lifters.pattern" || plain == "lifters")
      setter = "the family makes every candidate's lifter; change [family] or the base scene";
    else if (plain == "lifters.rows" && d.rows.given) setter = "family.rows sets it";
    else if ((plain == "mill.direction" || plain == "mill") && !d.directions.empty()) setter = "family.direction sets it";
    else if (plain == "fidelity" && !d.fidelity.empty()) setter = "screen.fidelity sets it";
    else if (plain == "wear.stages" && d.stages > 0) setter = "screen.stages sets it";
    else if (plain == "wear.stage_hours" && d.stage_hours > 0.0) setter = "screen.stage_hours sets it";
    if (o.find_first_of("\r\n") != std::string::npos) throw InputError(path, "--set " + key, "a value on one line");
    if (!setter.empty())
      throw InputError(path, "--set " + key, "a key the screen does not set for every candidate itself, but " + setter);
  }
}

// The base scene, with the overrides: its own errors name it (and the --set they come from),
// and say which screen file's screen.base it is (a comparison or screen file given there
// reads as a scene with unknown tables). Then what the family asks of it: its kinds of lifter
// against the profiles and areas listed, and, where a kind is not a trapezoid, every
// trapezoid parameter given.
void check_base_scene(const std::string& path, const tr::TableReader& s, const tr::TableReader& f, ScreenDef& d) {
  const Scene b = [&] {
    try {
      return load_scene(d.base_scene, d.overrides);
    } catch (const InputError& e) {
      throw InputError(e.file, e.where, e.expected + " (read as the scene file that " + path + "'s screen.base names)");
    }
  }();
  d.kinds = b.mill.kind_count();
  if (d.kinds > 1 && !d.profiles.empty())
    f.fail("profiles", "no family.profiles with a base scene of a pattern of " + std::to_string(d.kinds) +
                           " kinds of lifter (the family's trapezoid keys apply to every kind)");
  if (!d.equal_area_kinds.empty() && static_cast<int>(d.equal_area_kinds.size()) != d.kinds)
    s.fail("equal_area", "a list of " + std::to_string(d.kinds) + " profile file(s), one per kind of lifter of the "
                         "base scene, got " + std::to_string(d.equal_area_kinds.size()));
  if (d.kinds > 1 && !d.equal_area.empty() && d.equal_area != "base" && d.equal_area_kinds.empty())
    s.fail("equal_area", "\"base\" (each kind matched to its own kind's area in the base scene) or a list of " +
                             std::to_string(d.kinds) + " profile files, one per kind: the base scene has a pattern");
  for (int k = 0; k < d.kinds && d.profiles.empty(); ++k) {
    if (b.mill.kind(k).form == ProfileForm::Trapezoid) continue;
    const std::string whose = d.kinds > 1 ? "the base scene's kind " + std::to_string(k) + " ('" + b.mill.kind(k).name + "')"
                                          : std::string("the base scene's lifter");
    for (const char* key : {"height", "leading_face_angle", "trailing_face_angle"}) {
      const Axis& a = std::string(key) == "height" ? d.height_mm
                      : std::string(key) == "leading_face_angle" ? d.leading_deg : d.trailing_deg;
      if (!a.given && !(std::string(key) == "trailing_face_angle" && d.symmetric))
        f.missing(key, "a value: " + whose + " is not a trapezoid, so the family must give " +
                           std::string("height, top_width (or screen.equal_area) and both face angles"));
    }
    if (!d.top_width_mm.given && d.equal_area.empty())
      f.missing("top_width", "a value, or screen.equal_area: " + whose + " is not a trapezoid");
  }
}

}  // namespace

ScreenDef load_screen(const std::string& path, const std::vector<std::string>& overrides) {
  const toml::table root = parse_screen_file(path);
  ScreenDef d;
  d.name = fs::path(path).stem().string();
  tr::TableReader top(root, "", path, nullptr, {"screen", "family"});
  const toml::table* st = top.table("screen");
  if (!st) top.missing("screen", "a [screen] table with base = \"scene.toml\"");
  tr::TableReader s(*st, "screen", path, nullptr,
                    {"name", "base", "fidelity", "stages", "stage_hours", "sampling", "samples", "seed",
                     "equal_area", "power"});
  read_screen_table(path, s, d);
  const toml::table* ft = top.table("family");
  static const toml::table kEmpty;
  tr::TableReader f(ft ? *ft : kEmpty, "family", path, nullptr,
                    {"height", "top_width", "leading_face_angle", "trailing_face_angle", "symmetric", "rows",
                     "direction", "profiles"});
  read_family_table(path, f, s, d);
  if (d.sampling == Sampling::Grid) check_grid_size(path, ft, d);
  check_overrides(path, overrides, d);
  d.overrides = overrides;
  check_base_scene(path, s, f, d);
  return d;
}

std::vector<std::string> varying_parameters(const ScreenDef& d) {
  std::vector<std::string> v;
  if (!d.profiles.empty() && d.profiles.size() > 1) v.push_back("profile");
  if (d.height_mm.varies()) v.push_back("height_mm");
  if (d.top_width_mm.varies()) v.push_back("top_width_mm");
  if (d.leading_deg.varies()) v.push_back("leading_face_angle_deg");
  if (d.trailing_deg.varies()) v.push_back("trailing_face_angle_deg");
  if (d.rows.varies()) v.push_back("rows");
  if (d.directions.size() > 1) v.push_back("direction");
  return v;
}

namespace {

// The family's axes, in the order profile, height, top width, leading and trailing angle,
// rows, direction, with the base scene's values where the family gives none. The profile
// and direction axes hold indices into d.profiles and dirs.
std::vector<Axis> family_axes(const ScreenDef& d, const Scene& base, std::size_t dirs) {
  const TrapezoidDef& bt = base.mill.lifter.trapezoid;
  const bool base_trap = base.mill.lifter.form == ProfileForm::Trapezoid;
  auto filled = [](Axis a, double fallback) {
    if (!a.given) a.values = {fallback};
    return a;
  };
  auto indices = [](std::size_t n) {
    Axis a;
    for (std::size_t i = 0; i < n; ++i) a.values.push_back(double(i));
    return a;
  };
  return {indices(std::max<std::size_t>(1, d.profiles.size())),
          filled(d.height_mm, base_trap ? in_mm(bt.height_m) : 0.0),
          filled(d.top_width_mm, base_trap ? in_mm(bt.top_width_m) : 0.0),
          filled(d.leading_deg, base_trap ? deg_from_rad(bt.leading_face_angle_rad) : 0.0),
          filled(d.trailing_deg, base_trap ? deg_from_rad(bt.trailing_face_angle_rad) : 0.0),
          filled(d.rows, base.mill.rows),
          indices(dirs)};
}

// Every combination of the axes' values, the last axis varying fastest.
std::vector<std::vector<double>> grid_points(const std::vector<Axis>& axes) {
  std::vector<std::vector<double>> points;
  std::vector<std::size_t> idx(axes.size(), 0);
  for (;;) {
    std::vector<double> p;
    for (std::size_t a = 0; a < axes.size(); ++a) p.push_back(axes[a].values[idx[a]]);
    points.push_back(p);
    std::size_t a = axes.size();
    while (a > 0) {
      --a;
      if (++idx[a] < axes[a].values.size()) break;
      idx[a] = 0;
      if (a == 0) return points;
    }
  }
}

// Latin hypercube: every axis is cut into n strata and each stratum used once, in an order
// shuffled by the seed. Uniforms from the top 53 bits of mt19937_64, so the sample is the
// same on every platform (std::uniform_real_distribution is not).
std::vector<std::vector<double>> latin_hypercube_points(const std::vector<Axis>& axes, std::size_t n,
                                                        std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  std::vector<std::vector<double>> points(n, std::vector<double>(axes.size(), 0.0));
  for (std::size_t a = 0; a < axes.size(); ++a) {
    std::vector<std::size_t> perm(n);
    for (std::size_t i = 0; i < n; ++i) perm[i] = i;
    for (std::size_t i = n; i > 1; --i) std::swap(perm[i - 1], perm[rng() % i]);
    for (std::size_t i = 0; i < n; ++i) {
      const double u = (static_cast<double>(perm[i]) + uniform()) / static_cast<double>(n);
      const Axis& ax = axes[a];
      if (ax.is_range) {
        points[i][a] = ax.min + u * (ax.max - ax.min);
      } else {
        const std::size_t k = std::min(ax.values.size() - 1, static_cast<std::size_t>(u * ax.values.size()));
        points[i][a] = ax.values[k];
      }
    }
  }
  return points;
}

// The area each kind is matched to (0: none): the base kind's own, the listed file of its
// kind, or the one file's (a plain liner).
std::vector<double> matched_areas_m2(const ScreenDef& d, const Scene& base) {
  const int kinds = base.mill.kind_count();
  std::vector<double> area(static_cast<std::size_t>(kinds), 0.0);
  for (int k = 0; k < kinds; ++k) {
    double& a = area[static_cast<std::size_t>(k)];
    if (d.equal_area == "base") a = measure_profile(base.mill.kind(k).points).area_m2;
    else if (!d.equal_area_kinds.empty())
      a = measure_profile(load_profile(d.equal_area_kinds[static_cast<std::size_t>(k)]).points).area_m2;
    else if (!d.equal_area.empty()) a = measure_profile(load_profile(d.equal_area).points).area_m2;
  }
  return area;
}

// A candidate of a listed profile file: its measures.
void measure_listed_profile(Candidate& c) {
  const ProfileMetrics m = measure_profile(load_profile(c.profile_source).points);
  c.height_mm = in_mm(m.height_m);
  c.top_width_mm = in_mm(m.top_width_m);
  c.leading_deg = deg_from_rad(m.leading_face_angle_rad);
  c.trailing_deg = deg_from_rad(m.trailing_face_angle_rad);
  c.area_mm2 = in_mm2(m.area_m2);
}

// A trapezoid candidate at point p, each kind of the base scene's pattern: the family's value
// where it gives one, else the base kind's own (kind 0's is already in the point), the top
// width from the matched area where there is one. A kind that makes no valid lifter gives
// the candidate its reason for rejection.
void shape_trapezoid_kinds(const ScreenDef& d, const Scene& base, const std::vector<double>& ref_area_m2,
                           const std::vector<double>& p, Candidate& c) {
  const int kinds = base.mill.kind_count();
  for (int k = 0; k < kinds && c.reason.empty(); ++k) {
    const LifterProfile& kp = base.mill.kind(k);
    const bool own = k > 0 && kp.form == ProfileForm::Trapezoid;
    const TrapezoidDef& kt = kp.trapezoid;
    KindShape ks;
    ks.height_mm = own && !d.height_mm.given ? in_mm(kt.height_m) : p[1];
    ks.top_width_mm = own && !d.top_width_mm.given ? in_mm(kt.top_width_m) : p[2];
    ks.leading_deg = own && !d.leading_deg.given ? deg_from_rad(kt.leading_face_angle_rad) : p[3];
    ks.trailing_deg = d.symmetric ? ks.leading_deg
                      : own && !d.trailing_deg.given ? deg_from_rad(kt.trailing_face_angle_rad) : p[4];
    TrapezoidDef t;
    t.height_m = ks.height_mm * 1e-3;
    t.top_width_m = ks.top_width_mm * 1e-3;
    t.leading_face_angle_rad = rad_from_deg(ks.leading_deg);
    t.trailing_face_angle_rad = rad_from_deg(ks.trailing_deg);
    const std::string of_kind = kinds > 1 ? "kind " + std::to_string(k) + " ('" + kp.name + "'): " : "";
    try {
      const double target = ref_area_m2[static_cast<std::size_t>(k)];
      if (target > 0.0) {
        t.top_width_m = top_width_for_area(t, target, d.equal_area);
        ks.top_width_mm = in_mm(t.top_width_m);
      }
      const Polyline pts = trapezoid_points(t);
      validate_lifter_polyline(pts, "", "");
      ks.area_mm2 = in_mm2(measure_profile(pts).area_m2);
      if (!(ks.area_mm2 > 0.0)) c.reason = of_kind + "zero metal area";
    } catch (const InputError& e) {
      c.reason = of_kind + e.expected;
    }
    if (k == 0) {
      c.height_mm = ks.height_mm;
      c.top_width_mm = ks.top_width_mm;
      c.leading_deg = ks.leading_deg;
      c.trailing_deg = ks.trailing_deg;
      c.area_mm2 = ks.area_mm2;
    }
    if (kinds > 1) c.kinds.push_back(ks);
  }
}

}  // namespace

std::vector<Candidate> sample_family(const ScreenDef& d, const Scene& base) {
  const std::string base_dir = base.mill.direction == Direction::Bidirectional ? "bi" : "uni";
  const std::vector<std::string> dirs = d.directions.empty() ? std::vector<std::string>{base_dir} : d.directions;
  const std::vector<Axis> axes = family_axes(d, base, dirs.size());
  const std::vector<std::vector<double>> points =
      d.sampling == Sampling::Grid ? grid_points(axes)
                                   : latin_hypercube_points(axes, static_cast<std::size_t>(d.samples), d.seed);
  const std::vector<double> ref_area_m2 = matched_areas_m2(d, base);
  std::vector<Candidate> out;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto& p = points[i];
    Candidate c;
    c.sample = static_cast<int>(i);
    char name[32];
    std::snprintf(name, sizeof name, points.size() > 1000 ? "d%05zu" : "d%03zu", i);
    c.name = name;
    c.rows = static_cast<int>(p[5]);
    c.direction = dirs[static_cast<std::size_t>(p[6])];
    if (!d.profiles.empty()) {
      c.profile_source = d.profiles[static_cast<std::size_t>(p[0])];
      measure_listed_profile(c);
    } else {
      shape_trapezoid_kinds(d, base, ref_area_m2, p, c);
    }
    out.push_back(c);
  }
  return out;
}

void check_distinct_candidates(const std::vector<Candidate>& candidates, const std::string& screen_file) {
  // A design is its profile or shapes, its rows and its direction.
  auto design = [](const Candidate& c) {
    std::string key = c.profile_source + "|" + std::to_string(c.rows) + "|" + c.direction;
    auto add = [&key](double height, double top, double leading, double trailing) {
      for (double v : {height, top, leading, trailing}) key += "|" + io::format_exact(v);
    };
    add(c.height_mm, c.top_width_mm, c.leading_deg, c.trailing_deg);
    for (const KindShape& k : c.kinds) add(k.height_mm, k.top_width_mm, k.leading_deg, k.trailing_deg);
    return key;
  };
  std::map<std::string, const Candidate*> seen;
  for (const Candidate& c : candidates) {
    const auto [it, fresh] = seen.emplace(design(c), &c);
    if (!fresh)
      throw InputError(screen_file, "screen.samples",
                       "samples that are each another design, but " + it->second->name + " and " + c.name +
                           " drew the same value of every parameter (a Latin hypercube over listed values draws "
                           "one of them per sample): give the parameters as ranges {min, max}, use sampling = "
                           "\"grid\" for listed values, fewer samples or another seed");
  }
}

std::string designs_csv(const std::string& out) { return io::join_path(out, "designs.csv"); }
std::string rejected_csv(const std::string& out) { return io::join_path(out, "rejected.csv"); }
std::string ranking_csv(const std::string& out) { return io::join_path(out, "ranking.csv"); }
std::string design_dir(const std::string& out, const std::string& name) {
  return io::join_path(io::join_path(out, "designs"), name);
}
std::string task_status_path(const std::string& out, const std::string& name) {
  return io::join_path(design_dir(out, name), "task.status");
}

void write_candidates(const ScreenDef& d, std::vector<Candidate>& cands, const std::string& out) {
  const std::string dir = io::join_path(out, "candidates");
  io::ensure_dir(dir);
  // The base scene's tables, with the --set overrides put in as load_scene puts them.
  const toml::table base = d.overrides.empty() ? toml::parse_file(d.base_scene)
                                               : toml::parse(overridden_scene_toml(d.base_scene, d.overrides),
                                                             d.base_scene);
  std::string set_text;
  for (const std::string& o : d.overrides) set_text += " --set " + o;
  // A trapezoid with its top width written out (no match_area_of: the file says exactly
  // what was run).
  const auto trapezoid_text = [&](const std::string& name, const std::string& what, double h, double top, double lead,
                                  double trail) {
    std::ostringstream p;
    p << "# " << what << " of screen " << d.name << " (written by millwear screen)\n"
      << "name = \"" << name << "\"\nform = \"trapezoid\"\n"
      << "height = " << fmt(h) << "\n"
      << "top_width = " << fmt(top) << "\n"
      << "leading_face_angle = " << fmt(lead) << "\n"
      << "trailing_face_angle = " << fmt(trail) << "\n";
    return p.str();
  };
  for (Candidate& c : cands) {
    if (!c.reason.empty()) continue;
    const std::string scene_path = io::join_path(dir, c.name + ".toml");
    // The profile: a trapezoid, or a copy of the listed profile file (a measured CSV stays
    // one); a pattern: one trapezoid per kind, NAME-kK-profile.toml.
    std::string ext = fs::path(c.profile_source).extension().string();
    for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    const std::string profile_name = c.name + (ext == ".csv" ? "-profile.csv" : "-profile.toml");
    const std::string profile_path = io::join_path(dir, profile_name);
    std::string profile;
    std::vector<std::pair<std::string, std::string>> kind_files;  // path, text
    if (!c.profile_source.empty()) {
      profile = io::read_file(c.profile_source);
    } else if (c.kinds.empty()) {
      profile = trapezoid_text(c.name, "candidate " + c.name, c.height_mm, c.top_width_mm, c.leading_deg,
                               c.trailing_deg);
    } else {
      for (std::size_t k = 0; k < c.kinds.size(); ++k) {
        const KindShape& ks = c.kinds[k];
        const std::string kname = c.name + "-k" + std::to_string(k);
        kind_files.emplace_back(io::join_path(dir, kname + "-profile.toml"),
                                trapezoid_text(kname, "kind " + std::to_string(k) + " of candidate " + c.name,
                                               ks.height_mm, ks.top_width_mm, ks.leading_deg, ks.trailing_deg));
      }
    }
    // The scene: the base scene's tables with the candidate's changes.
    toml::table t = base;
    t.insert_or_assign("name", c.name);
    if (!d.fidelity.empty()) t.insert_or_assign("fidelity", d.fidelity);
    if (auto* lif = t["lifters"].as_table()) {
      if (kind_files.empty()) {
        lif->erase("pattern");
        lif->insert_or_assign("profile", profile_name);
      } else {
        lif->erase("profile");
        toml::array names;
        for (std::size_t k = 0; k < kind_files.size(); ++k)
          names.push_back(c.name + "-k" + std::to_string(k) + "-profile.toml");
        lif->insert_or_assign("pattern", std::move(names));
      }
      lif->insert_or_assign("rows", static_cast<int64_t>(c.rows));
      // A drawn lifter is new: the base's start_hours (when a worn liner it starts from was
      // measured) would add those hours to the candidate's life. A measured scan keeps them.
      if (ext != ".csv") lif->erase("start_hours");
    }
    if (auto* mill = t["mill"].as_table()) {
      mill->insert_or_assign("direction", c.direction == "bi" ? "bidirectional" : "forward");
      if (c.direction != "bi") mill->erase("reverse_every");
    }
    if (d.stages > 0 || d.stage_hours > 0.0) {
      if (!t["wear"].as_table()) t.insert_or_assign("wear", toml::table{});
      auto* w = t["wear"].as_table();
      if (d.stages > 0) w->insert_or_assign("stages", static_cast<int64_t>(d.stages));
      if (d.stage_hours > 0.0) w->insert_or_assign("stage_hours", d.stage_hours);
    }
    std::ostringstream os;
    os << "# candidate " << c.name << " of screen " << d.name << ": base scene " << d.base_scene
       << (set_text.empty() ? "" : " with" + set_text + ",")
       << " with its lifter, rows and direction (written by millwear screen)\n"
       << toml::toml_formatter{t} << "\n";
    if (kind_files.empty()) {
      io::write_file_atomic(profile_path, profile);
      c.profile_file = "candidates/" + profile_name;
    }
    for (std::size_t k = 0; k < kind_files.size(); ++k) {
      io::write_file_atomic(kind_files[k].first, kind_files[k].second);
      c.kinds[k].profile_file = "candidates/" + fs::path(kind_files[k].first).filename().string();
    }
    if (!c.kinds.empty()) c.profile_file = c.kinds.front().profile_file;
    io::write_file_atomic(scene_path, os.str());
    c.scene_file = "candidates/" + c.name + ".toml";
    try {
      const Scene s = load_scene(scene_path);
      build_scene_mill(s);
      check_scene(s, scene_path);  // a lifter narrower than the smoothing would vanish
      // Where the family varies the direction, a "bi" design that never reverses within its
      // history is the one-way design again, ranked as another.
      const double history_h = s.wear.stages * s.wear.stage_hours;
      if (!d.directions.empty() && s.mill.direction == Direction::Bidirectional &&
          !(s.mill.reverse_every_hours < history_h))
        throw InputError(scene_path, "mill.reverse_every",
                         "a reversal within the design's history (" + std::to_string(s.wear.stages) + " stages of " +
                             io::format_number(s.wear.stage_hours) + " h) for direction = bi; every " +
                             io::format_number(s.mill.reverse_every_hours) +
                             " h it never reverses and runs one way: shorten reverse_every or run longer");
      if (c.area_mm2 <= 0.0) c.area_mm2 = measure_profile(s.mill.lifter.points).area_m2 * 1e6;
    } catch (const InputError& e) {
      c.reason = (e.where.empty() ? "" : e.where + ": ") + e.expected;
      std::error_code ec;
      fs::remove(scene_path, ec);
      fs::remove(profile_path, ec);
      for (const auto& kf : kind_files) fs::remove(kf.first, ec);
      for (KindShape& ks : c.kinds) ks.profile_file.clear();
      c.scene_file.clear();
      c.profile_file.clear();
    }
  }
}

namespace {
const std::vector<std::string> kDesignColumns = {
    "task", "design", "sample", "height_mm", "top_width_mm", "leading_face_angle_deg", "trailing_face_angle_deg",
    "rows", "direction", "area_mm2", "profile_source", "scene_file", "profile_file"};

// Every kind's columns of a pattern's candidates, after the columns above.
const std::vector<std::string> kKindColumns = {"height_mm", "top_width_mm", "leading_face_angle_deg",
                                               "trailing_face_angle_deg", "area_mm2", "profile_file"};
std::string kind_column(std::size_t k, const std::string& c) { return "kind" + std::to_string(k) + "_" + c; }

std::vector<io::CsvCell> design_cells(long long task, const Candidate& c, std::size_t kinds) {
  std::vector<io::CsvCell> cells{task, c.name, c.sample, c.height_mm, c.top_width_mm, c.leading_deg, c.trailing_deg,
                                 c.rows, c.direction, c.area_mm2, c.profile_source, c.scene_file, c.profile_file};
  for (std::size_t k = 0; k < kinds; ++k) {
    if (k >= c.kinds.size()) {  // a candidate rejected at an earlier kind
      for (std::size_t i = 0; i < kKindColumns.size(); ++i) cells.emplace_back(std::string());
      continue;
    }
    const KindShape& s = c.kinds[k];
    for (const io::CsvCell& x : std::vector<io::CsvCell>{s.height_mm, s.top_width_mm, s.leading_deg, s.trailing_deg,
                                                         s.area_mm2, s.profile_file})
      cells.push_back(x);
  }
  return cells;
}
}  // namespace

void write_design_tables(const std::string& out, const std::vector<Candidate>& cands) {
  std::size_t kinds = 0;
  for (const Candidate& c : cands) kinds = std::max(kinds, c.kinds.size());
  std::vector<std::string> cols = kDesignColumns;
  for (std::size_t k = 0; k < kinds; ++k)
    for (const std::string& n : kKindColumns) cols.push_back(kind_column(k, n));
  // Exact numbers: the tasks read them back as the candidate's record.
  io::CsvTable good(cols, io::CsvOptions{10, true});
  std::vector<std::string> rej_cols = cols;
  rej_cols.erase(rej_cols.begin());
  rej_cols.push_back("reason");
  io::CsvTable bad(rej_cols);
  long long task = 0;
  for (const Candidate& c : cands) {
    if (c.reason.empty()) {
      good.add_row(design_cells(task++, c, kinds));
    } else {
      auto cells = design_cells(0, c, kinds);
      cells.erase(cells.begin());
      cells.push_back(c.reason);
      bad.add_row(cells);
    }
  }
  good.write(designs_csv(out));
  bad.write(rejected_csv(out));
}

std::vector<Candidate> read_designs(const std::string& out) {
  // The list the screen wrote, as its screen.key records it: rows cut or values edited since
  // would run, collect and rank other designs under these names.
  const std::string key_file = io::join_path(out, "screen.key");
  if (io::file_exists(key_file)) {
    const std::string recorded = io::find_value(io::read_key_values(key_file), "designs");
    if (!recorded.empty() && recorded != io::stable_hash_hex(io::read_file(designs_csv(out))))
      throw InputError(designs_csv(out), "",
                       "the list of designs this screen wrote (its hash is in screen.key), but it was changed since "
                       "(rows cut, values edited): run the screen again with --resume, which writes it anew");
  }
  const io::CsvData t = io::read_csv(designs_csv(out));
  // Every column, also when the file holds no row to read them from: a damaged designs.csv is
  // refused, not read as a screen of nothing.
  for (const std::string& col : kDesignColumns) t.column(col);
  std::vector<Candidate> v;
  for (std::size_t r = 0; r < t.row_count(); ++r) {
    Candidate c;
    c.name = t.text(r, t.column("design"));
    c.sample = static_cast<int>(t.number(r, "sample"));
    c.height_mm = t.number(r, "height_mm");
    c.top_width_mm = t.number(r, "top_width_mm");
    c.leading_deg = t.number(r, "leading_face_angle_deg");
    c.trailing_deg = t.number(r, "trailing_face_angle_deg");
    c.rows = static_cast<int>(t.number(r, "rows"));
    c.direction = t.text(r, t.column("direction"));
    c.area_mm2 = t.number(r, "area_mm2");
    c.profile_source = t.text(r, t.column("profile_source"));
    c.scene_file = t.text(r, t.column("scene_file"));
    c.profile_file = t.text(r, t.column("profile_file"));
    for (std::size_t k = 0; t.has_column(kind_column(k, "area_mm2")); ++k) {
      KindShape s;
      s.height_mm = t.number(r, kind_column(k, "height_mm"));
      s.top_width_mm = t.number(r, kind_column(k, "top_width_mm"));
      s.leading_deg = t.number(r, kind_column(k, "leading_face_angle_deg"));
      s.trailing_deg = t.number(r, kind_column(k, "trailing_face_angle_deg"));
      s.area_mm2 = t.number(r, kind_column(k, "area_mm2"));
      s.profile_file = t.text(r, t.column(kind_column(k, "profile_file")));
      c.kinds.push_back(s);
    }
    if (static_cast<std::size_t>(t.number(r, "task")) != r || !io::is_valid_design_name(c.name))
      throw InputError(t.path, "line " + std::to_string(t.row_line[r]), "task numbers 0, 1, 2, ... in order and a design name");
    v.push_back(c);
  }
  return v;
}

}  // namespace millwear::screen
