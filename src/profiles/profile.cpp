// Lifter profile files (TOML, mm and degrees) -> lifter polylines (m, rad), and the profile
// metrics printed by `millwear profile`. toml++ stays inside this file.
#include "common/units.hpp"
#include "profiles/profile.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <set>
#include <sstream>
#include <string_view>

#include "common/errors.hpp"
#include "common/names.hpp"
#include "common/text.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"

namespace millwear {

namespace {

// A file name's extension in lower case (".csv", ".toml").
std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}
// Feet must lie on the shell line; file values are in mm, so 1 nm is "exactly zero" for
// anything a person types, and still catches a foot written at 0.001 mm.
constexpr double kFootTolM = 1e-9;

namespace fs = std::filesystem;

std::string line_of(const toml::node& n) {
  return "line " + std::to_string(n.source().begin.line);
}

// 5 m bounds a lifter's height and top width (the largest mills are 12 m across); any point of
// a polyline profile within kMaxPointMm (profile.hpp).
constexpr double kMaxLifterMm = 5000.0;

// A number (integer or float) or an InputError naming the key.
double number_at(const toml::table& t, std::string_view key, const std::string& file,
                 const std::string& expected) {
  const toml::node* n = t.get(key);
  if (!n) throw InputError(file, std::string(key), "missing; expected " + expected);
  const auto v = n->value<double>();
  if (!n->is_number() || !v || !std::isfinite(*v))
    throw InputError(file, std::string(key), "expected " + expected + " (" + line_of(*n) + ")");
  return *v;
}

std::string string_at(const toml::table& t, std::string_view key, const std::string& file,
                      const std::string& expected) {
  const toml::node* n = t.get(key);
  if (!n) throw InputError(file, std::string(key), "missing; expected " + expected);
  if (!n->is_string())
    throw InputError(file, std::string(key), "expected " + expected + " (" + line_of(*n) + ")");
  return *n->value<std::string>();
}

double face_angle_at(const toml::table& t, std::string_view key, const std::string& file) {
  const double deg = number_at(t, key, file, "a face angle in degrees, 0 <= angle < 90");
  if (!(deg >= 0.0 && deg < 90.0))
    throw InputError(file, std::string(key),
                     "expected a face angle in degrees, 0 <= angle < 90 (got " +
                         short_number(deg) + ")");
  return rad_from_deg(deg);
}

// Walk a face from its foot (pts[0]) until the polyline first reaches half the height and
// return the angle of the chord foot -> that point from the radial (+y) direction, positive
// when the face leans towards +x (into the lifter, for a face walked from the trailing foot).
double face_angle_from_foot(const Polyline& pts, double height) {
  if (pts.size() < 2 || !(height > 0.0)) return 0.0;
  const Vec2 foot = pts.front();
  const double y_half = 0.5 * height;
  for (std::size_t i = 0; i + 1 < pts.size(); ++i) {
    const Vec2 a = pts[i], b = pts[i + 1];
    if (b.y >= y_half) {
      const double t = (b.y == a.y) ? 1.0 : std::clamp((y_half - a.y) / (b.y - a.y), 0.0, 1.0);
      const Vec2 p = a + t * (b - a);
      return std::atan2(p.x - foot.x, p.y - foot.y);
    }
  }
  return 0.0;
}

const std::set<std::string_view>& keys_for(ProfileForm form) {
  static const std::set<std::string_view> trapezoid{
      "name", "description", "form", "height", "top_width", "leading_face_angle",
      "trailing_face_angle", "match_area_of"};
  static const std::set<std::string_view> polyline{"name", "description", "form", "points"};
  return form == ProfileForm::Trapezoid ? trapezoid : polyline;
}

std::string key_list(const std::set<std::string_view>& keys) {
  std::string s;
  for (std::string_view k : keys) s += (s.empty() ? "" : ", ") + std::string(k);
  return s;
}

}  // namespace

void check_points_span(const Polyline& points_m, const std::string& file, const std::string& where) {
  if (points_m.empty()) return;
  double x0 = points_m[0].x, x1 = x0, y0 = points_m[0].y, y1 = y0;
  for (const Vec2& p : points_m) {
    x0 = std::min(x0, p.x), x1 = std::max(x1, p.x);
    y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
  }
  const double span_mm = in_mm(std::max(x1 - x0, y1 - y0));
  if (span_mm >= kMinSpanMm) return;
  throw InputError(file, where,
                   "millimetres, spanning at least " + short_number(kMinSpanMm) + " mm across as a lifter does; these points span " +
                       short_number(span_mm) + " mm: are they in metres?");
}

namespace {

Polyline read_points(const toml::table& t, const std::string& file) {
  const toml::node* n = t.get("points");
  const std::string expected = "an array of [x, y] pairs in mm, trailing foot to leading foot";
  if (!n) throw InputError(file, "points", "missing; expected " + expected);
  const toml::array* arr = n->as_array();
  if (!arr) throw InputError(file, "points", "expected " + expected + " (" + line_of(*n) + ")");
  // A drawn profile has tens of points, checked pair by pair (check_no_point_on_another_edge):
  // a scan of thousands goes in a measured CSV, whose checks take any size.
  constexpr std::size_t kMaxDrawnPoints = 5000;
  if (arr->size() > kMaxDrawnPoints)
    throw InputError(file, "points",
                     "expected at most " + std::to_string(kMaxDrawnPoints) + " points in a drawn profile, got " +
                         std::to_string(arr->size()) + " (" + line_of(*n) +
                         "); a scan of more goes in a measured profile, a CSV x_mm,y_mm read at any size");
  Polyline pts;
  for (std::size_t i = 0; i < arr->size(); ++i) {
    const toml::node& e = *arr->get(i);
    const std::string key = "points[" + std::to_string(i) + "]";
    const toml::array* pair = e.as_array();
    if (!pair || pair->size() != 2 || !pair->get(0)->is_number() || !pair->get(1)->is_number())
      throw InputError(file, key, "expected a pair [x, y] of numbers in mm (" + line_of(e) + ")");
    const double x = *pair->get(0)->value<double>(), y = *pair->get(1)->value<double>();
    if (!(std::abs(x) <= kMaxPointMm && std::abs(y) <= kMaxPointMm))
      throw InputError(file, key, "expected numbers in mm within +-100000 (" + line_of(e) + ")");
    pts.push_back({x * kMm, y * kMm});
  }
  check_points_span(pts, file, "points");
  return pts;
}

// A point typed onto one of the line's other edges (within a micrometre) pinches the lifter
// into two parts joined at a point. The exact test of validate_lifter_polyline sees such a
// point on whichever side the conversion to metres rounded it, so it is found here first, by
// distance, naming the point and the edge (or the point it repeats). A drawn profile has tens
// of points: every pair.
void check_no_point_on_another_edge(const Polyline& pts, const std::string& file) {
  constexpr double kTouchM = 1e-6;  // far below any drawing's resolution, far above rounding
  const auto mm = [](Vec2 p) { return "(" + short_number(p.x * 1e3) + ", " + short_number(p.y * 1e3) + " mm)"; };
  // A point given twice (a foot copied, a corner pasted again) is named as such first.
  for (std::size_t j = 1; j < pts.size(); ++j)
    for (std::size_t i = 0; i < j; ++i)
      if (length(pts[j] - pts[i]) <= kTouchM)
        throw InputError(file, "points[" + std::to_string(j) + "]",
                         "expected each point once; this point " + mm(pts[j]) + " is points[" + std::to_string(i) +
                             "] again");
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (std::size_t j = 0; j + 1 < pts.size(); ++j) {
      if (j == i || j + 1 == i) continue;  // the point's own edges
      if (distance_to_polyline(pts[i], Polyline{pts[j], pts[j + 1]}) > kTouchM) continue;
      throw InputError(file, "points[" + std::to_string(i) + "]",
                       "expected a polyline that does not touch itself; this point " + mm(pts[i]) +
                           " lies on the edge from points[" + std::to_string(j) + "] to points[" +
                           std::to_string(j + 1) + "]");
    }
}

// A name is also a CSV file name (`profile --csv`) and a manifest field: the one rule for names.
// `key` names where the name came from: "name", or the file name of a TOML profile without
// that key or of a measured CSV (which has no keys: the file must be renamed).
enum class NameFrom { Key, TomlFileName, CsvFileName };
void check_name(const std::string& name, const std::string& file, NameFrom from) {
  if (is_safe_name(name)) return;
  const char* advice = from == NameFrom::TomlFileName ? " (the profile has no name key, so its file name is used: give it one)"
                       : from == NameFrom::CsvFileName ? " (a measured profile is named after its file: rename the file)"
                                                       : "";
  throw InputError(file, from == NameFrom::CsvFileName ? "file name" : "name",
                   "expected " + safe_name_rule() + advice);
}

LifterProfile load_profile_impl(const std::string& path, std::vector<std::string>& chain) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw InputError(path, "", "expected an existing, readable profile file");
  const std::string canonical = fs::weakly_canonical(path, ec).string();
  if (std::find(chain.begin(), chain.end(), canonical) != chain.end()) {
    std::string loop;
    for (auto it = std::find(chain.begin(), chain.end(), canonical); it != chain.end(); ++it)
      loop += fs::path(*it).filename().string() + " -> ";
    throw InputError(path, "match_area_of",
                     "expected a chain of profiles that ends; match_area_of comes back to this file (" + loop +
                         fs::path(canonical).filename().string() + ")");
  }
  chain.push_back(canonical);

  toml::table root;
  try {
    root = toml::parse_file(path);
  } catch (const toml::parse_error& e) {
    throw InputError(path, "line " + std::to_string(e.source().begin.line),
                     "expected a TOML profile file: " + std::string(e.description()));
  }

  // A scene or comparison file given where a profile belongs: say what the file is.
  if (!root.contains("form"))
    for (const char* table : {"mill", "lifters", "comparison"})
      if (root.contains(table))
        throw InputError(path, "form",
                         std::string("a lifter profile (name, form and its shape); this file has a [") + table +
                             "] table: it is a " + (std::string(table) == "comparison" ? "comparison" : "scene") +
                             " file, and a scene names its profile in lifters.profile");
  const std::string form_name = string_at(root, "form", path, "\"trapezoid\" or \"polyline\"");
  ProfileForm form;
  if (form_name == "trapezoid") {
    form = ProfileForm::Trapezoid;
  } else if (form_name == "polyline") {
    form = ProfileForm::Polyline;
  } else {
    throw InputError(path, "form", "expected \"trapezoid\" or \"polyline\" (got \"" + form_name +
                                       "\", " + line_of(*root.get("form")) + ")");
  }

  const auto& allowed = keys_for(form);
  for (auto&& [key, node] : root) {
    if (!allowed.count(key.str()))
      throw InputError(path, std::string(key.str()),
                       "unknown key for form = \"" + form_name + "\" (" + line_of(node) +
                           "); expected one of: " + key_list(allowed));
  }

  LifterProfile prof;
  prof.source_file = path;
  prof.form = form;
  prof.name = root.contains("name") ? string_at(root, "name", path, "a string")
                                    : fs::path(path).stem().string();
  check_name(prof.name, path, root.contains("name") ? NameFrom::Key : NameFrom::TomlFileName);
  if (root.contains("description")) string_at(root, "description", path, "a string");

  if (form == ProfileForm::Trapezoid) {
    TrapezoidDef t;
    const double h_mm = number_at(root, "height", path, "a height in mm in (0, 5000]");
    if (!(h_mm > 0.0 && h_mm <= kMaxLifterMm))
      throw InputError(path, "height",
                       "expected a height in mm in (0, 5000] (got " + short_number(h_mm) + ")");
    t.height_m = h_mm * kMm;
    t.leading_face_angle_rad = face_angle_at(root, "leading_face_angle", path);
    t.trailing_face_angle_rad = face_angle_at(root, "trailing_face_angle", path);

    const bool has_top = root.contains("top_width");
    const bool has_match = root.contains("match_area_of");
    if (has_top && has_match)
      throw InputError(path, "match_area_of",
                       "expected either top_width or match_area_of, not both");
    if (has_match) {
      const std::string other = string_at(root, "match_area_of", path, "a profile file path");
      const fs::path other_path = fs::path(path).parent_path() / other;
      if (!fs::is_regular_file(other_path, ec))
        throw InputError(path, "match_area_of",
                         "expected an existing profile file; not found: " + other_path.string());
      // A measured lifter (CSV) refers to nothing further; a TOML one may, and the chain
      // catches a loop.
      const bool measured = lower_extension(other_path) == ".csv";
      LifterProfile ref;
      try {
        ref = measured ? parse_measured_profile(io::read_file(other_path.string()), other_path.string())
                       : load_profile_impl(other_path.string(), chain);
      } catch (const InputError& e) {
        // The referred file's own problem, said with the key that led to it.
        if (e.where == "match_area_of" && e.file != other_path.string()) throw;  // a loop, said where it closes
        throw InputError(e.file, e.where, e.expected + " (the profile match_area_of names in " + path + ")");
      }
      const double target = measure_profile(ref.points).area_m2;
      t.top_width_m = top_width_for_area(t, target, path);
      prof.referenced_files.push_back(other_path.lexically_normal().string());
      prof.referenced_files.insert(prof.referenced_files.end(), ref.referenced_files.begin(),
                                   ref.referenced_files.end());
    } else if (has_top) {
      const double w_mm = number_at(root, "top_width", path, "a top width in mm in (0, 5000]");
      if (!(w_mm > 0.0 && w_mm <= kMaxLifterMm))
        throw InputError(path, "top_width",
                         "expected a top width in mm in (0, 5000] (got " + short_number(w_mm) + ")");
      t.top_width_m = w_mm * kMm;
    } else {
      throw InputError(path, "top_width", "missing; expected a top width in mm > 0 "
                                          "(or match_area_of = \"<other profile>\")");
    }
    prof.trapezoid = t;
    prof.points = trapezoid_points(t);
    // Faces near 90 degrees lean a base kilometres wide out of a few millimetres of height:
    // held to the bounds of a drawn polyline's points.
    // The base is centred: its feet reach out by the same half-width on both sides.
    double reach_m = 0.0;
    for (const Vec2& p : prof.points)
      if (!(std::abs(p.x) <= reach_m)) reach_m = std::isnan(p.x) ? HUGE_VAL : std::abs(p.x);
    if (!(reach_m * 1e3 <= kMaxPointMm))
      throw InputError(path, t.leading_face_angle_rad >= t.trailing_face_angle_rad ? "leading_face_angle"
                                                                                    : "trailing_face_angle",
                       "expected face angles that keep the base within +-" + short_number(kMaxPointMm) +
                           " mm of the centre; at " + short_number(in_mm(t.height_m)) + " mm high its feet reach x = +-" +
                           short_number(reach_m * 1e3) + " mm");
    check_points_span(prof.points, path, "height");  // a lifter drawn in metres
    validate_lifter_polyline(prof.points, path, "top_width");
  } else {
    prof.points = read_points(root, path);
    check_no_point_on_another_edge(prof.points, path);
    validate_lifter_polyline(prof.points, path, "points");
  }
  chain.pop_back();
  return prof;
}

}  // namespace

Polyline trapezoid_points(const TrapezoidDef& t) {
  const double h = t.height_m;
  const double run_lead = h * std::tan(t.leading_face_angle_rad);
  const double run_trail = h * std::tan(t.trailing_face_angle_rad);
  const double half_base = 0.5 * (t.top_width_m + run_lead + run_trail);
  return {{-half_base, 0.0},
          {-half_base + run_trail, h},
          {half_base - run_lead, h},
          {half_base, 0.0}};
}

double top_width_for_area(const TrapezoidDef& t, double area_m2, const std::string& file) {
  // A = h * (top + base) / 2 with base = top + h (tan lead + tan trail).
  const double h = t.height_m;
  const double runs = std::tan(t.leading_face_angle_rad) + std::tan(t.trailing_face_angle_rad);
  const double top = (area_m2 - 0.5 * h * h * runs) / h;
  if (!(h > 0.0) || !(top > 0.0) || !std::isfinite(top)) {
    std::ostringstream msg;
    msg << "expected a profile whose area (" << in_mm2(area_m2)
        << " mm^2) a trapezoid of this height and these face angles can match with a "
           "positive top width (the faces alone give "
        << 0.5 * h * h * runs * 1e6 << " mm^2)";
    throw InputError(file, "match_area_of", msg.str());
  }
  return top;
}

ProfileMetrics measure_profile(const Polyline& pts) {
  ProfileMetrics m;
  if (pts.size() < 2) return m;
  // The polyline runs trailing foot -> over the top -> leading foot; closed by the base it is
  // a clockwise ring, so the area is the magnitude of the shoelace sum.
  m.area_m2 = area(pts);
  for (const Vec2& p : pts) m.height_m = std::max(m.height_m, p.y);
  m.base_width_m = pts.back().x - pts.front().x;

  // Top width: x-extent of the vertices within 2% of the height of the top (a flat top of a
  // trapezoid measures exactly its top width; a rounded worn top measures its plateau).
  const double y_band = 0.98 * m.height_m;
  double xmin = std::numeric_limits<double>::infinity(), xmax = -xmin;
  for (const Vec2& p : pts) {
    if (p.y >= y_band) {
      xmin = std::min(xmin, p.x);
      xmax = std::max(xmax, p.x);
    }
  }
  m.top_width_m = xmax >= xmin ? xmax - xmin : 0.0;

  m.trailing_face_angle_rad = face_angle_from_foot(pts, m.height_m);
  Polyline from_lead(pts.rbegin(), pts.rend());
  for (Vec2& p : from_lead) p.x = -p.x;  // mirror so the same walk measures the leading face
  m.leading_face_angle_rad = face_angle_from_foot(from_lead, m.height_m);
  return m;
}

void validate_lifter_polyline(const Polyline& pts, const std::string& file,
                              const std::string& key) {
  if (pts.size() < 3)
    throw InputError(file, key, "expected at least 3 points (trailing foot, top, leading foot)");
  for (const Vec2& p : pts)
    if (!std::isfinite(p.x) || !std::isfinite(p.y))
      throw InputError(file, key, "expected finite coordinates");
  if (std::abs(pts.front().y) > kFootTolM || std::abs(pts.back().y) > kFootTolM)
    throw InputError(file, key, "expected both feet (first and last point) on the shell, y = 0");
  if (!(pts.front().x < pts.back().x))
    throw InputError(file, key,
                     "expected the trailing foot (first point) at smaller x than the leading "
                     "foot (last point)");
  for (std::size_t i = 1; i + 1 < pts.size(); ++i)
    if (!(pts[i].y > kFootTolM))
      throw InputError(file, key,
                       "expected every point between the feet above the shell, y > 0 (point " +
                           std::to_string(i) + ")");
  // The lifter closed by its base must be a simple polygon: this catches a face crossing
  // itself or the other face, and repeated points.
  if (!is_simple(pts))
    throw InputError(file, key, "expected a polyline that does not cross or touch itself");
}

namespace {

// Points closer than this are one point measured twice: a micrometre is far below any
// gauge's resolution and far above the rounding of a millimetre written with 10 digits.
constexpr double kSamePointM = 1e-6;
// The ends of a measured surface may lie this far above the shell line and still count as on
// it (the rounding of a file written in mm).
constexpr double kEndTolM = 1e-6;

}  // namespace

Polyline lifter_of_surface(const Polyline& s, const std::string& file, const std::string& key) {
  if (s.size() < 3) throw InputError(file, key, "expected at least 3 points along the surface");
  std::size_t top = 0;
  for (std::size_t i = 1; i < s.size(); ++i)
    if (s[i].y > s[top].y) top = i;
  if (!(s[top].y > kEndTolM))
    throw InputError(file, key, "expected a lifter: some point above the shell line, y > 0");
  if (s.front().y > kEndTolM || s.back().y > kEndTolM)
    throw InputError(file, key,
                     "expected both ends of the surface at or below the shell line, y <= 0 (a profile from "
                     "shell to shell; the first point is at y = " + short_number(s.front().y * 1e3) +
                         " mm, the last at y = " + short_number(s.back().y * 1e3) + " mm)");
  // From the top outwards to the first point on the shell line (within kEndTolM, as the ends)
  // or below it on either side: a point a rounding error above the line is a foot, not a
  // lifter point that validate_lifter_polyline would find on the line.
  std::size_t left = top, right = top;
  while (left > 0 && s[left - 1].y > kEndTolM) --left;
  while (right + 1 < s.size() && s[right + 1].y > kEndTolM) ++right;
  auto crossing = [](Vec2 below, Vec2 above) {  // the point at y = 0 on [below, above]
    if (below.y >= 0.0) return Vec2{below.x, 0.0};  // on the line within kEndTolM: the foot
    const double t = below.y / (below.y - above.y);
    return Vec2{below.x + t * (above.x - below.x), 0.0};
  };
  // An end just above the shell line (rounding) is its own foot.
  const Vec2 foot_l = left == 0 ? Vec2{s[0].x, 0.0} : crossing(s[left - 1], s[left]);
  const Vec2 foot_r = right + 1 == s.size() ? Vec2{s.back().x, 0.0} : crossing(s[right + 1], s[right]);
  // One lifter per surface: the rest is shell plate and wears as shell. Metal above the line
  // outside the lifter of a tenth of the lifter's area is a second lifter that would be taken
  // for shell; gauge noise on plates at the line holds far less.
  double outside_m2 = 0.0, lifter_m2 = 0.0;
  std::size_t highest = 0;  // the highest point outside the lifter (for the message)
  for (std::size_t i = 0; i + 1 < s.size(); ++i) {
    // The area above y = 0 under edge i (the part of a crossing edge above the line).
    const Vec2 a = s[i], b = s[i + 1];
    double above = 0.0;
    if (a.y > 0.0 && b.y > 0.0) above = 0.5 * (a.y + b.y) * std::abs(b.x - a.x);
    else if (a.y > 0.0 || b.y > 0.0) above = 0.5 * std::max(a.y, b.y) * std::max(a.y, b.y) / std::abs(a.y - b.y) * std::abs(b.x - a.x);
    // The lifter's edges run from the one into point `left` to the one out of point `right`.
    if (i + 1 < left || i > right) {
      outside_m2 += above;
      const std::size_t k = s[i].y > s[i + 1].y ? i : i + 1;
      if (s[k].y > s[highest].y) highest = k;
    } else {
      lifter_m2 += above;
    }
  }
  if (outside_m2 > 0.1 * lifter_m2)
    throw InputError(file, key,
                     "expected one lifter per surface, the rest at or below the shell line; outside the lifter (x = " +
                         short_number(foot_l.x * 1e3) + " to " + short_number(foot_r.x * 1e3) + " mm) it holds " +
                         short_number(in_mm2(outside_m2)) + " mm^2 above the line, rising to y = " +
                         short_number(s[highest].y * 1e3) + " mm at x = " + short_number(s[highest].x * 1e3) +
                         " mm (a scan of one liner unit per file; a pattern of kinds for hi-lo liners)");
  const std::size_t first = left == 0 ? 1 : left;
  const std::size_t last = right + 1 == s.size() ? right - 1 : right;
  Polyline lifter{foot_l};
  for (std::size_t i = first; i <= last; ++i) lifter.push_back(s[i]);
  lifter.push_back(foot_r);
  validate_lifter_polyline(lifter, file, key);
  return lifter;
}

namespace {

// The `# pitch_mm = P` comment line of a measured profile, if any: {P in m, its line}.
std::pair<double, int> pitch_comment(const std::string& text, const std::string& name) {
  std::pair<double, int> found{0.0, 0};
  std::size_t pos = text.compare(0, 3, io::kUtf8Bom) == 0 ? 3 : 0;
  for (int line = 1; pos <= text.size(); ++line) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string l = trim(text.substr(pos, end - pos));
    pos = end + 1;
    if (l.empty() || l[0] != '#') continue;
    l = trim(l.substr(1));
    // Any case, and a ':' for the '=' (a near miss that would otherwise read as a comment and
    // the scan as one lifter): both then refused below unless written as the line asks.
    std::string head = l.substr(0, 8);
    std::transform(head.begin(), head.end(), head.begin(), [](unsigned char c) { return std::tolower(c); });
    if (head != "pitch_mm" || (l.size() > 8 && l[8] != ' ' && l[8] != '\t' && l[8] != '=' && l[8] != ':')) continue;
    const std::string where = "line " + std::to_string(line);
    if (found.second != 0)
      throw InputError(name, where, "one pitch_mm line (line " + std::to_string(found.second) + " gives it already)");
    std::string rest = trim(l.substr(8));
    const std::string expected =
        "'# pitch_mm = P' with P the liner unit's pitch along the shell, a number of mm in (0, 100000]";
    if (rest.empty() || rest[0] != '=') throw InputError(name, where, expected);
    rest = trim(rest.substr(1));
    const std::size_t hash = rest.find('#');  // a comment after the value
    if (hash != std::string::npos) rest = trim(rest.substr(0, hash));
    if (rest.find('.') == std::string::npos) std::replace(rest.begin(), rest.end(), ',', '.');  // decimal comma
    char* stop = nullptr;
    const double mm = rest.empty() ? std::nan("") : std::strtod(rest.c_str(), &stop);
    if (rest.empty() || *stop != '\0' || !std::isfinite(mm) || !(mm > 0.0) || mm > kMaxPointMm)
      throw InputError(name, where, expected + ", got '" + rest + "'");
    found = {mm * kMm, line};
    if (end == text.size()) break;
  }
  return found;
}

// A scan runs from one side of the lifter to the other: its ends are its leftmost and
// rightmost points (within kScanEndTolerance of its width; a gauge's last reading may step
// back a little). A closed outline (the plate's underside drawn back to the start) or a
// surface written back to its first point ends inside its width: refused at the point that
// lies beyond its ends, where it was later taken for a surface crossing itself, unplaced.
constexpr double kScanEndTolerance = 0.01;
void check_scan_ends(const Polyline& raw, const io::CsvData& d, const std::string& name) {
  std::size_t lo = 0, hi = 0;
  for (std::size_t i = 1; i < raw.size(); ++i) {
    if (raw[i].x < raw[lo].x) lo = i;
    if (raw[i].x > raw[hi].x) hi = i;
  }
  const double tol = kScanEndTolerance * (raw[hi].x - raw[lo].x);
  const double left = std::min(raw.front().x, raw.back().x), right = std::max(raw.front().x, raw.back().x);
  const bool left_out = left - raw[lo].x > tol;
  if (!left_out && raw[hi].x - right <= tol) return;
  const std::size_t at = left_out ? lo : hi;
  throw InputError(name, "line " + std::to_string(d.row_line[at]),
                   "a surface from one side of the lifter to the other, its first and last points its leftmost and "
                   "rightmost: the point here, at x = " + short_number(raw[at].x * 1e3) + " mm, lies " +
                       short_number(std::abs(raw[at].x - (left_out ? left : right)) * 1e3) +
                       " mm beyond both ends (x = " + short_number(raw.front().x * 1e3) + " and " +
                       short_number(raw.back().x * 1e3) +
                       " mm). Is it a closed outline, or the base written back to the start? Give the surface alone");
}

}  // namespace

LifterProfile parse_measured_profile(const std::string& text, const std::string& name) {
  io::CsvData d = io::parse_csv(io::strip_comment_lines(text), name);
  const std::size_t cx = d.column("x_mm"), cy = d.column("y_mm");
  Polyline raw;
  for (std::size_t r = 0; r < d.row_count(); ++r) {
    const double x = d.number(r, cx), y = d.number(r, cy);
    if (!(std::abs(x) <= kMaxPointMm && std::abs(y) <= kMaxPointMm))
      throw InputError(name, "line " + std::to_string(d.row_line[r]),
                       "x_mm and y_mm finite and within +-100000 mm");
    raw.push_back({x * kMm, y * kMm});
  }
  if (raw.size() < 3)
    throw InputError(name, "line " + std::to_string(d.header_line + 1),
                     "at least 3 points x_mm,y_mm after the header");
  check_points_span(raw, name, "x_mm,y_mm");
  LifterProfile prof;
  prof.source_file = name;
  prof.form = ProfileForm::Measured;
  prof.name = fs::path(name).stem().string();
  check_name(prof.name, name, NameFrom::CsvFileName);
  // Points in order along the surface; a scan from the leading side is turned round.
  if (raw.front().x > raw.back().x) std::reverse(raw.begin(), raw.end());
  Polyline s;
  for (const Vec2& p : raw)
    if (s.empty() || length(p - s.back()) > kSamePointM) s.push_back(p);
  // Noise on a steep face can step back over the points before it: cut such loops out.
  Polygon loop;
  s = without_loops(s, &loop);
  prof.dropped_points = static_cast<int>(raw.size() - s.size());
  // A file that comes back to where it began is all loop: nothing of a surface is left.
  if (s.size() < 3 && !loop.empty())
    throw InputError(name, "x_mm,y_mm",
                     "an open surface from one foot to the other; the points close on themselves around a loop of " +
                         short_number(std::abs(signed_area(loop)) * 1e6) + " mm^2 and leave " + std::to_string(s.size()) +
                         (s.size() == 1 ? " point" : " points") + " of surface (is the base written back to the first point?)");
  check_scan_ends(raw, d, name);
  if (!is_simple_open(s))
    throw InputError(name, "x_mm,y_mm", "expected a surface that does not cross itself");
  prof.measured = s;
  prof.points = lifter_of_surface(s, name, "x_mm,y_mm");
  // A gauge's noise makes loops of a fraction of a square millimetre; a loop holding a real
  // share of the lifter is points out of order, and cutting it would change the lifter.
  const double loop_m2 = loop.empty() ? 0.0 : std::abs(signed_area(loop));
  const double lifter_m2 = std::abs(signed_area(prof.points));
  if (loop_m2 > kMaxNoiseLoopShare * lifter_m2)
    throw InputError(name, "x_mm,y_mm",
                     "a surface that does not cross itself: it crosses itself at x = " + short_number(loop[0].x * 1e3) +
                         ", y = " + short_number(loop[0].y * 1e3) + " mm around a loop of " + short_number(in_mm2(loop_m2)) +
                         " mm^2, " + short_number(100.0 * loop_m2 / lifter_m2) +
                         "% of the lifter (loops of gauge noise, cut out, hold under " +
                         short_number(100.0 * kMaxNoiseLoopShare) + "%): are the points in order along the surface?");
  // A whole unit's scan: its ends one pitch apart.
  const auto [pitch_m, pitch_line] = pitch_comment(io::with_newline_ends(text), name);
  if (pitch_line != 0) {
    const double width = s.back().x - s.front().x;
    if (std::abs(width - pitch_m) > kPitchTolerance * pitch_m)
      throw InputError(name, "line " + std::to_string(pitch_line),
                       "pitch_mm = " + short_number(in_mm(pitch_m)) + ": a scan of one whole liner unit, its first and last "
                       "points one pitch apart (within " + short_number(100.0 * kPitchTolerance) + "%); its points reach from x = " +
                           short_number(s.front().x * 1e3) + " to " + short_number(s.back().x * 1e3) + " mm, " +
                           short_number(width * 1e3) + " mm");
    // The unit repeats around the mill: its last point is the next copy's first, so the two
    // ends are one place up to the gauge's mismatch.
    const double step_m = s.back().y - s.front().y;
    if (std::abs(step_m) > kPitchTolerance * pitch_m)
      throw InputError(name, "line " + std::to_string(pitch_line),
                       "pitch_mm = " + short_number(in_mm(pitch_m)) + ": a scan of one whole liner unit, its first and last "
                       "points at one height (the unit repeats, and each end meets the next copy's other end; within " +
                           short_number(kPitchTolerance * pitch_m * 1e3) + " mm, " + short_number(100.0 * kPitchTolerance) +
                           "% of the pitch); its ends are at y = " + short_number(s.front().y * 1e3) + " and " +
                           short_number(s.back().y * 1e3) + " mm");
    prof.unit_pitch_m = pitch_m;
    prof.pitch_line = pitch_line;
  }
  return prof;
}

LifterProfile load_profile(const std::string& path) {
  if (lower_extension(path) == ".csv") {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
      throw InputError(path, "", "expected an existing, readable profile file");
    return parse_measured_profile(io::read_file(path), path);
  }
  std::vector<std::string> chain;
  return load_profile_impl(path, chain);
}

namespace {

// What --csv writes for a profile: a comment line naming it, then its points in mm.
std::string profile_csv_text(const LifterProfile& p) {
  std::string comment = std::string(kProfileCsvHeader) + " " + p.name + " from " + p.source_file;
  for (char& c : comment)
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';  // one comment line, whatever the path holds
  std::string text = comment + "\nx_mm,y_mm\n";
  char line[96];
  for (const Vec2& v : p.points) {
    std::snprintf(line, sizeof line, "%.6f,%.6f\n", v.x * 1e3, v.y * 1e3);
    text += line;
  }
  return text;
}

}  // namespace

void check_profile_csv_targets(const std::vector<LifterProfile>& profiles, const std::string& dir) {
  namespace fs = std::filesystem;
  for (std::size_t i = 0; i < profiles.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j)
      if (profiles[i].name == profiles[j].name)
        throw InputError(profiles[i].source_file, "name",
                         "expected a name different from " + profiles[j].source_file + " (both would be written to " +
                             profiles[i].name + ".csv)");
    // A measured scan's name is its file's: --csv into its own folder would overwrite it; so
    // would a profile named as a file another profile's match_area_of reads.
    const fs::path target = fs::path(dir) / (profiles[i].name + ".csv");
    for (const LifterProfile& input : profiles) {
      std::vector<std::string> read = input.referenced_files;
      read.insert(read.begin(), input.source_file);
      for (const std::string& f : read) {
        std::error_code ec;
        if (fs::equivalent(target, f, ec))
          throw InputError("", "--csv",
                           "a folder other than the one holding " + f + ", which " + input.source_file +
                               (f == input.source_file ? " is" : " reads") + " (" + target.string() +
                               " would overwrite it)");
      }
    }
    // Nor a file of the user's (a scan under the profile's name): only an earlier --csv's, or
    // the same points as one written before the comment line was.
    std::error_code ec;
    if (!fs::exists(target, ec)) continue;
    const std::string have = io::read_file(target.string()), text = profile_csv_text(profiles[i]);
    if (have.rfind(kProfileCsvHeader, 0) != 0 && have != text.substr(text.find('\n') + 1))
      throw InputError("", "--csv",
                       "a folder without a file " + profiles[i].name + ".csv other than one `millwear profile --csv` "
                       "wrote (its first line \"" + kProfileCsvHeader + " ...\"); " + target.string() +
                           " is another (or an older millwear's, of other points), which the profile's file would "
                           "replace: delete it to replace it");
  }
}

std::vector<std::string> write_profile_csvs(const std::vector<LifterProfile>& profiles, const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir)) throw InputError("", "--csv", "expected a writable directory: " + dir);
  std::vector<std::string> files;
  for (const LifterProfile& p : profiles) {
    files.push_back((fs::path(dir) / (p.name + ".csv")).string());
    io::write_file_atomic(files.back(), profile_csv_text(p));
  }
  return files;
}

}  // namespace millwear
