#include "study/surveys.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "common/errors.hpp"
#include "common/text.hpp"
#include "io/csv.hpp"
#include "profiles/profile.hpp"

namespace millwear::validation {

namespace {

constexpr double kMm = 1e-3;

std::string line_of(const io::CsvData& d, std::size_t row) { return "line " + std::to_string(d.row_line[row]); }

// The area between a survey and the shell line y = 0 over its span: the metal under it (the
// polar map's correction left out; it sets a tolerance's scale).
double area_under(const Polyline& s) {
  double ymin = 0.0;
  for (const Vec2& p : s) ymin = std::min(ymin, p.y);
  Polygon region = s;
  region.push_back({s.back().x, ymin - 1.0});
  region.push_back({s.front().x, ymin - 1.0});
  region = clip_half_plane(region, [](Vec2 p) { return p.y; });
  return region.size() < 3 ? 0.0 : std::abs(signed_area(region));
}

// The area of the largest loop in a polyline (0 if it does not cross itself).
double largest_loop_m2(const Polyline& line, Polygon* loop = nullptr) {
  Polygon l;
  without_loops(line, &l);
  if (loop) *loop = l;
  return l.empty() ? 0.0 : std::abs(signed_area(l));
}

// A survey's points follow the surface in order. Shuffled points, or two lifters' points in
// one block, cross the surface over itself, and its areas and distances mean nothing: a
// loop of over kMaxNoiseLoopShare of the metal under the survey is refused, naming the line
// where it closes. Smaller loops, a gauge's noise on a steep face (as a measured profile's,
// profiles/profile.hpp), are kept as measured: each adds or takes its own sliver of area.
void check_in_order(const Survey& s, const std::vector<std::size_t>& lines, const std::string& name) {
  Polygon loop;
  const double loop_m2 = largest_loop_m2(s.profile_m, &loop);
  const double limit_m2 = kMaxNoiseLoopShare * area_under(s.profile_m);
  if (loop_m2 <= limit_m2) return;
  // The shortest run of points from the survey's start with such a loop: its last point.
  std::size_t lo = 3, hi = s.profile_m.size();  // fewer than 3 points make no loop
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    const Polyline head(s.profile_m.begin(), s.profile_m.begin() + static_cast<std::ptrdiff_t>(mid));
    if (largest_loop_m2(head) > limit_m2) hi = mid;
    else lo = mid + 1;
  }
  char buf[400];
  std::snprintf(buf, sizeof buf,
                "points in order along the surface: the survey at %s h crosses itself at x = %.4g, y = %.4g mm "
                "around a loop of %.4g mm^2 (loops of a gauge's noise, under %.0f%% of the metal under the "
                "survey, are taken as measured); are its points in order, and of one lifter?",
                io::format_number(s.hours).c_str(), loop[0].x / kMm, loop[0].y / kMm, loop_m2 / (kMm * kMm),
                100.0 * kMaxNoiseLoopShare);
  throw InputError(name, "line " + std::to_string(lines[hi - 1]), buf);
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
    // 1e6 h is over a century of operation; 1e5 mm (100 m) is past any liner.
    if (!(h >= 0.0 && h <= 1e6))
      throw InputError(name, line_of(d, r), "operating hours in [0, 1e6] in column hours, found '" + d.text(r, ch) + "'");
    if (!(std::abs(x) <= 1e5 && std::abs(y) <= 1e5))
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
    if (!s.profile_m.empty() && s.profile_m.back() == p)
      throw InputError(name, line_of(d, r), "a point different from the one before (repeated point)");
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
