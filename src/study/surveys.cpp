#include "study/surveys.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "common/errors.hpp"
#include "common/text.hpp"
#include "common/units.hpp"
#include "geometry/edge_tree.hpp"
#include "io/csv.hpp"
#include "profiles/profile.hpp"
#include "scene/limits.hpp"

namespace millwear::validation {

namespace {

std::string line_of(const io::CsvData& d, std::size_t row) { return "line " + std::to_string(d.row_line[row]); }

// The area between a survey and the shell line y = 0 over its span: the metal under it (the
// polar map's correction left out; it sets a tolerance's scale).
double area_under(const Polyline& s) {
  const Polygon region = region_above_zero(s);
  return region.size() < 3 ? 0.0 : std::abs(signed_area(region));
}

// Whether segments ab and cd cross at a point inside both (touching does not count).
bool cross_inside(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const double d1 = cross(b - a, c - a), d2 = cross(b - a, d - a), d3 = cross(d - c, a - c), d4 = cross(d - c, b - c);
  return ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0)) && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0));
}

// A survey's points follow the surface in order. Shuffled points, or two lifters' points in
// one block, cross the surface over itself, and its areas and distances mean nothing. Where
// two of its edges cross, the points between them close a loop: a loop of more than
// kMaxNoiseLoopShare of the metal under the survey is refused, naming the two edges' lines;
// smaller loops, a gauge's noise on a steep face (as a measured profile's,
// profiles/profile.hpp), are kept as measured. Points that run back over the surface without
// crossing it (a lifter given twice) are refused when cutting their loops out changes the
// metal under the survey by more than that share.
void check_in_order(const Survey& s, const std::vector<std::size_t>& lines, const std::string& name) {
  const Polyline& p = s.profile_m;
  const double metal_m2 = area_under(p);
  const double limit_m2 = kMaxNoiseLoopShare * metal_m2;
  double worst_m2 = 0.0;
  std::size_t first = 0, last = 0;  // the worst loop's edges (first, first + 1) and (last, last + 1)
  // A laser scan gives a survey of a million points: the edges that may cross edge j are found
  // in a tree of bounding boxes (about log n tests each, not n), and a loop's area from running
  // sums of the shoelace terms (taken about the first point, to keep their digits), not by
  // walking the loop.
  const Vec2 origin = p.front();
  std::vector<double> shoelace(p.size(), 0.0);  // shoelace[k]: cross terms of edges 0 .. k-1
  for (std::size_t k = 0; k + 1 < p.size(); ++k)
    shoelace[k + 1] = shoelace[k] + cross(p[k] - origin, p[k + 1] - origin);
  const EdgeTree tree(p, 0.0);
  for (std::size_t j = 2; j + 1 < p.size(); ++j)
    tree.last_hit(box_of(p[j], p[j + 1]), 0, j - 2, [&](std::size_t i) {
      if (!cross_inside(p[i], p[i + 1], p[j], p[j + 1])) return false;
      // The loop: the crossing point, then p[i + 1] .. p[j].
      const Vec2 d = p[i + 1] - p[i], e = p[j + 1] - p[j];
      const Vec2 x = p[i] + (cross(p[j] - p[i], e) / cross(d, e)) * d - origin;
      const double loop_m2 =
          0.5 * std::abs(cross(x, p[i + 1] - origin) + (shoelace[j] - shoelace[i + 1]) + cross(p[j] - origin, x));
      // The largest loop; of equal ones, the one that starts first along the survey.
      if (loop_m2 > worst_m2 || (loop_m2 == worst_m2 && worst_m2 > 0.0 && j == last && i < first)) {
        worst_m2 = loop_m2;
        first = i;
        last = j;
      }
      return false;  // every crossing edge before j, not only the last
    });
  char buf[480];
  if (worst_m2 > limit_m2) {
    const std::size_t a = std::min(lines[first], lines[last + 1]), b = std::max(lines[first], lines[last + 1]);
    std::snprintf(buf, sizeof buf,
                  "points in order along the surface: the survey at %s h crosses itself between lines %zu and %zu "
                  "around a loop of %.4g mm^2 (loops of a gauge's noise, under %.0f%% of the %.4g mm^2 of metal "
                  "under the survey, are taken as measured); are its points in order, and of one lifter?",
                  io::format_number(s.hours).c_str(), a, b, worst_m2 / (kMm * kMm), 100.0 * kMaxNoiseLoopShare,
                  metal_m2 / (kMm * kMm));
    throw InputError(name, "line " + std::to_string(b), buf);
  }
  const double cut_m2 = area_under(without_loops(p));
  if (std::abs(metal_m2 - cut_m2) <= kMaxNoiseLoopShare * std::max(metal_m2, cut_m2)) return;
  std::snprintf(buf, sizeof buf,
                "points in order along the surface: the survey at %s h runs back over itself; as given the metal "
                "under it is %.4g mm^2, with its loops cut out %.4g mm^2; are its points in order, and of one lifter?",
                io::format_number(s.hours).c_str(), metal_m2 / (kMm * kMm), cut_m2 / (kMm * kMm));
  throw InputError(name, "line " + std::to_string(s.first_line), buf);
}

}  // namespace

SurveyCsv parse_survey_csv(const std::string& text, const std::string& name) {
  const std::string stripped = io::strip_comment_lines(text);
  // Comment lines become blank lines, so parse_csv's line numbers are the file's.
  SurveyCsv csv{io::parse_csv(stripped, name), 1};
  csv.header_line = csv.data.header_line;
  return csv;
}

std::string comment_lines(const std::string& comment) {
  std::string out;
  std::size_t pos = 0;
  while (!comment.empty() && pos <= comment.size()) {
    std::size_t end = comment.find('\n', pos);
    if (end == std::string::npos) end = comment.size();
    out += "# " + comment.substr(pos, end - pos) + "\n";
    pos = end + 1;
  }
  return out;
}

std::vector<Survey> parse_surveys(const std::string& text, const std::string& name) {
  const SurveyCsv csv = parse_survey_csv(text, name);
  const io::CsvData& d = csv.data;
  const std::size_t ch = d.column("hours"), cx = d.column("x_mm"), cy = d.column("y_mm");
  if (d.row_count() == 0)
    throw InputError(name, "line " + std::to_string(csv.header_line + 1), "survey rows hours,x_mm,y_mm after the header");

  std::vector<Survey> surveys;
  std::vector<std::vector<std::size_t>> lines;  // each survey's points' lines in the file
  std::map<double, std::size_t> seen;  // hours -> first line of its block
  for (std::size_t r = 0; r < d.row_count(); ++r) {
    const double h = d.number(r, ch), x = d.number(r, cx), y = d.number(r, cy);
    if (!(h >= 0.0 && h <= kMaxHours))
      throw InputError(name, line_of(d, r), "operating hours in [0, 1e6] in column hours, found '" + shown_text(d.text(r, ch)) + "'");
    if (!(std::abs(x) <= kMaxPointMm && std::abs(y) <= kMaxPointMm))
      throw InputError(name, line_of(d, r), "x_mm and y_mm within +-100000 mm");
    if (surveys.empty() || surveys.back().hours != h) {
      auto it = seen.find(h);
      if (it != seen.end())
        throw InputError(name, line_of(d, r),
                         "one block of consecutive rows per survey; the survey at " + trim(d.text(r, ch)) +
                             " h already appeared from line " + std::to_string(it->second));
      if (!surveys.empty() && surveys.back().profile_m.size() < 2)
        throw InputError(name, "line " + std::to_string(surveys.back().first_line),
                         "at least 2 points in the survey at " + io::format_number(surveys.back().hours) + " h");
      Survey s;
      s.hours = h;
      s.first_line = d.row_line[r];
      seen[h] = s.first_line;
      surveys.push_back(s);
      lines.emplace_back();
    }
    Survey& s = surveys.back();
    const Vec2 p{x * kMm, y * kMm};
    // A point written again (a scan's repeated reading) adds nothing to the survey: dropped.
    if (!s.profile_m.empty() && s.profile_m.back() == p) continue;
    s.profile_m.push_back(p);
    lines.back().push_back(d.row_line[r]);
  }
  if (surveys.back().profile_m.size() < 2)
    throw InputError(name, "line " + std::to_string(surveys.back().first_line),
                     "at least 2 points in the survey at " + io::format_number(surveys.back().hours) + " h");
  for (std::size_t k = 0; k < surveys.size(); ++k) {
    Survey& s = surveys[k];
    if (s.profile_m.front().x > s.profile_m.back().x) {
      std::reverse(s.profile_m.begin(), s.profile_m.end());
      std::reverse(lines[k].begin(), lines[k].end());
    }
    check_points_span(s.profile_m, name, "line " + std::to_string(s.first_line));
    check_in_order(s, lines[k], name);
    // Its area and area error are over the span between its ends: a span of no width has none.
    if (!(s.profile_m.back().x - s.profile_m.front().x > 0.0))
      throw InputError(name, "line " + std::to_string(s.first_line),
                       "a survey spanning a width along the shell (its first and last points at different x_mm); "
                       "the survey at " + io::format_number(s.hours) + " h starts and ends at x = " +
                           io::format_number(s.profile_m.front().x / kMm) + " mm");
  }
  return surveys;
}


std::vector<double> survey_hours(const std::vector<Survey>& surveys) {
  std::vector<double> h;
  for (const Survey& s : surveys) h.push_back(s.hours);
  return h;
}

std::string format_surveys(const std::vector<Survey>& surveys, const std::string& comment) {
  const std::string out = comment_lines(comment);
  io::CsvTable t({"hours", "x_mm", "y_mm"});
  for (const Survey& s : surveys)
    for (const Vec2& p : s.profile_m) t.add_row({s.hours, p.x / kMm, p.y / kMm});
  return out + t.str();
}

}  // namespace millwear::validation
