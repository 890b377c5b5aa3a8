#include "study/area_surveys.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/errors.hpp"
#include "common/text.hpp"
#include "common/units.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "scene/limits.hpp"
#include "study/calibration.hpp"

namespace millwear::validation {

namespace {

const char* const kEitherFormat =
    "columns hours,x_mm,y_mm (measured profiles, one block of rows per survey) or hours,area_mm2 "
    "(measured lifter areas, one row per lifter survey; or hours,area_loss_mm2)";

}  // namespace

AreaSurveys parse_area_surveys(const std::string& text, const std::string& name) {
  const SurveyCsv csv = parse_survey_csv(text, name);
  const io::CsvData& d = csv.data;
  const std::string header = "line " + std::to_string(csv.header_line);
  if (!d.has_column("hours")) throw InputError(name, header, "a column named hours (operating hours of each survey)");
  const bool area = d.has_column("area_mm2"), loss = d.has_column("area_loss_mm2");
  if (area && loss) throw InputError(name, header, "one of the columns area_mm2 or area_loss_mm2, not both");
  if (!area && !loss) throw InputError(name, header, kEitherFormat);
  const std::string value_col = area ? "area_mm2" : "area_loss_mm2";
  if (d.row_count() == 0)
    throw InputError(name, "line " + std::to_string(csv.header_line + 1),
                     "area survey rows hours," + value_col + " after the header");

  AreaSurveys out;
  out.losses = loss;
  const std::size_t ch = d.column("hours"), cv = d.column(value_col);
  for (std::size_t r = 0; r < d.row_count(); ++r) {
    const std::string line = "line " + std::to_string(d.row_line[r]);
    const double h = d.number(r, ch), v = d.number(r, cv);
    // 1e10 mm^2 (100 m x 100 m) is past any lifter.
    if (!(h >= 0.0 && h <= kMaxHours))
      throw InputError(name, line, "operating hours in [0, 1e6] in column hours, found '" + shown_text(d.text(r, ch)) + "'");
    if (area && !(v > 0.0 && v <= 1e10))
      throw InputError(name, line, "a lifter area in (0, 1e10] (mm^2) in column area_mm2, found '" + shown_text(d.text(r, cv)) + "'");
    if (loss && !(std::abs(v) <= 1e10))
      throw InputError(name, line, "an area loss within +-1e10 (mm^2) in column area_loss_mm2, found '" + shown_text(d.text(r, cv)) + "'");
    out.surveys.push_back({h, v * kMm2, d.row_line[r]});
  }
  return out;
}


std::string format_area_surveys(const AreaSurveys& surveys, const std::string& comment) {
  io::CsvTable t({"hours", surveys.losses ? "area_loss_mm2" : "area_mm2"});
  for (const AreaSurvey& s : surveys.surveys) t.add_row({s.hours, s.value_m2 / kMm2});
  return comment_lines(comment) + t.str();
}

std::vector<double> survey_hours(const AreaSurveys& surveys) {
  std::vector<double> h;
  for (const AreaSurvey& s : surveys.surveys) h.push_back(s.hours);
  return h;
}

MeasuredAreas measured_areas(const AreaSurveys& surveys, double new_area_m2, double start_hours) {
  MeasuredAreas m;
  m.reference_m2 = new_area_m2;
  if (!surveys.losses) {
    double sum = 0.0;
    int n = 0;
    for (const AreaSurvey& s : surveys.surveys)
      if (std::fabs(s.hours - start_hours) <= kSameHoursTolerance) { sum += s.value_m2; ++n; }
    if (n > 0) {
      m.reference_m2 = sum / n;
      m.reference_measured = true;
    }
  }
  for (const AreaSurvey& s : surveys.surveys) {
    m.area_m2.push_back(surveys.losses ? m.reference_m2 - s.value_m2 : s.value_m2);
    m.loss_m2.push_back(surveys.losses ? s.value_m2 : m.reference_m2 - s.value_m2);
  }
  return m;
}

void check_areas_shrink(const AreaSurveys& surveys, double new_area_m2, double start_hours, const std::string& file,
                        bool one_shape) {
  const MeasuredAreas m = measured_areas(surveys, new_area_m2, start_hours);
  const char* reference = m.reference_measured ? "the survey at the start" : "the scene's lifter at the start";
  const auto mm2 = [](double m2) { return io::format_number(in_mm2(m2), 6); };
  const auto at_start = [&](const AreaSurvey& s) { return std::fabs(s.hours - start_hours) <= kSameHoursTolerance; };
  // The loss since the start is nothing at the start: rows there (several lifters, each
  // reported against their mean, say) average to 0 within a gauge's noise (kGainNoiseShare of
  // the reference area, as elsewhere); a larger mean counts from elsewhere.
  if (surveys.losses) {
    double sum_m2 = 0.0;
    int n = 0;
    std::size_t first_line = 0;
    for (const AreaSurvey& s : surveys.surveys)
      if (at_start(s)) {
        if (n == 0) first_line = s.line;
        sum_m2 += s.value_m2;
        ++n;
      }
    const double mean_m2 = n > 0 ? sum_m2 / n : 0.0;
    if (std::abs(mean_m2) > kGainNoiseShare * m.reference_m2)
      throw InputError(file, "line " + std::to_string(first_line),
                       "area losses averaging 0 at the history's start (" + io::format_number(start_hours) +
                           " h), within a gauge's noise (" + io::format_number(100.0 * kGainNoiseShare) +
                           "% of the lifter's " + mm2(m.reference_m2) + " mm^2, " +
                           mm2(kGainNoiseShare * m.reference_m2) + " mm^2): area_loss_mm2 is the area lost since "
                           "then, and " + (n == 1 ? std::string("this row gives ") : "the " + std::to_string(n) +
                           " rows there, from this one, average ") + mm2(mean_m2) +
                           " mm^2; give losses counted from the start, or the areas themselves (hours,area_mm2)");
  }
  // Rows at the start measure the scene's lifter as cast: within a factor of two of its area
  // (a casting is a few % off its drawing), or they are in other units (cm^2) or of another
  // lifter, and every loss counted from them would be too.
  if (!surveys.losses && m.reference_measured && one_shape &&
      !(m.reference_m2 >= 0.5 * new_area_m2 && m.reference_m2 <= 2.0 * new_area_m2)) {
    std::size_t first_line = 0;
    for (const AreaSurvey& s : surveys.surveys)
      if (at_start(s)) {
        first_line = s.line;
        break;
      }
    throw InputError(file, "line " + std::to_string(first_line),
                     "lifter areas at the history's start (" + io::format_number(start_hours) +
                         " h) within a factor of two of the scene's lifter (" + mm2(new_area_m2) +
                         " mm^2), as cast; they average " + mm2(m.reference_m2) +
                         " mm^2: are they in other units (mm^2 expected), or of another lifter?");
  }
  // No survey can have lost the whole lifter: the wear it asks for cannot be simulated.
  for (std::size_t i = 0; i < surveys.surveys.size(); ++i)
    if (!(m.loss_m2[i] < m.reference_m2))
      throw InputError(file, "line " + std::to_string(surveys.surveys[i].line),
                       "an area loss smaller than the lifter's area (" + std::to_string(m.reference_m2 / kMm2) +
                           " mm^2, " + reference + "); this survey's is " +
                           std::to_string(m.loss_m2[i] / kMm2) + " mm^2");
  // Wear removes metal: a survey after the start above the lifter it wore from, by more than
  // a gauge's noise, is not a survey of that lifter, whatever the other rows lost. Areas
  // judged by the drawing (no row at the start) may also be of a casting bigger than drawn;
  // losses count from the lifter as it was at the start, whatever its casting.
  const bool drawing = !surveys.losses && !m.reference_measured;
  const bool judged = one_shape || !drawing;  // else: of which of the pattern's lifters?
  const double share = kGainNoiseShare + (drawing ? kCastOverDrawingShare : 0.0);
  for (std::size_t i = 0; i < surveys.surveys.size() && judged; ++i) {
    const AreaSurvey& s = surveys.surveys[i];
    const double gain_m2 = m.area_m2[i] - m.reference_m2;
    if (at_start(s) || !(gain_m2 > share * m.reference_m2)) continue;
    const std::string allowed =
        drawing ? "a gauge's noise and a casting bigger than drawn (" + io::format_number(100.0 * kGainNoiseShare) +
                      "% + " + io::format_number(100.0 * kCastOverDrawingShare) + "% of it, " +
                      mm2(share * m.reference_m2) + " mm^2; a row at the start, hours " +
                      io::format_number(start_hours) + ", gives the lifter as cast, the exact reference)"
                : "a gauge's noise (" + io::format_number(100.0 * kGainNoiseShare) + "% of it, " +
                      mm2(share * m.reference_m2) + " mm^2)";
    throw InputError(file, "line " + std::to_string(s.line),
                     "a lifter area no larger than the lifter's at the start (" + mm2(m.reference_m2) + " mm^2, " +
                         reference + ") by more than " + allowed + ": wear removes metal, and the " +
                         "survey at " + io::format_number(s.hours) + " h " +
                         (surveys.losses ? "gives a loss of " + mm2(s.value_m2) + " mm^2, "
                                         : "has " + mm2(m.area_m2[i]) + " mm^2, ") +
                         mm2(gain_m2) + " mm^2 more");
  }
  double moment = 0.0;
  for (std::size_t i = 0; i < surveys.surveys.size(); ++i)
    moment += (surveys.surveys[i].hours - start_hours) * m.loss_m2[i];
  if (!(moment > 0.0) && !surveys.surveys.empty())
    throw InputError(file, "line " + std::to_string(surveys.surveys.back().line),
                     std::string("lifter areas that shrink with operating hours (a wear rate is fitted to the area "
                                 "lost); these ") +
                         (surveys.losses ? "area losses are not positive" : "areas do not shrink with time") +
                         " (the reference area is " + reference +
                         ", " + std::to_string(m.reference_m2 / kMm2) + " mm^2)");
}

void check_area_losses_above_noise(const AreaSurveys& surveys, double new_area_m2, double start_hours,
                                   const std::string& file) {
  const MeasuredAreas m = measured_areas(surveys, new_area_m2, start_hours);
  std::size_t most = surveys.surveys.size();
  for (std::size_t i = 0; i < surveys.surveys.size(); ++i)
    if (surveys.surveys[i].hours > start_hours + kSameHoursTolerance &&
        (most == surveys.surveys.size() || m.loss_m2[i] > m.loss_m2[most]))
      most = i;
  if (most == surveys.surveys.size()) return;  // no survey after the start: refused elsewhere
  const double noise_m2 = kGainNoiseShare * m.reference_m2;
  if (m.loss_m2[most] > noise_m2) return;
  const auto mm2 = [](double m2) { return io::format_number(in_mm2(m2), 6); };
  throw InputError(file, "line " + std::to_string(surveys.surveys[most].line),
                   "a survey that lost more area than a gauge's noise (" + io::format_number(100.0 * kGainNoiseShare) +
                       "% of the lifter's " + mm2(m.reference_m2) + " mm^2 at the start, " + mm2(noise_m2) +
                       " mm^2) to fit a wear rate to; the survey that lost the most, at " +
                       io::format_number(surveys.surveys[most].hours) + " h, lost " + mm2(m.loss_m2[most]) +
                       " mm^2 (a survey later in the lifter's life shows its wear)");
}

void check_surveys_from_start(const Measurements& measured, double start_hours, const std::string& from,
                              const std::string& file) {
  const std::vector<double> hours = measured.hours();
  const std::vector<std::size_t> lines = measured.lines();
  for (std::size_t i = 0; i < hours.size(); ++i)
    if (hours[i] < start_hours - kSameHoursTolerance)
      throw InputError(file, "line " + std::to_string(lines[i]),
                       "surveys at or after the history's start, " + from + " (" + io::format_number(start_hours) +
                           " h): the wear before it is not simulated; this survey is at " + io::format_number(hours[i]) + " h");
}

void check_surveys_within_stages(const Measurements& measured, const Scene& scene, double reach,
                                 const std::string& file) {
  const std::vector<double> hours = measured.hours();
  if (hours.empty()) return;
  const Scene s = scene_for_survey_hours(scene, hours, 0.0, reach);
  if (s.wear.stages <= kMaxStages) return;
  const std::size_t last = static_cast<std::size_t>(std::max_element(hours.begin(), hours.end()) - hours.begin());
  const double since_h = reach * (hours[last] - scene.wear.start_hours);
  char buf[480];
  std::snprintf(buf, sizeof buf,
                "surveys a history reaches in at most %d stages (as wear.stages) of the scene's wear.stage_hours, "
                "%s h%s: the survey at %s h needs %d (to %s h from the history's start); give the scene a "
                "stage_hours of at least %s h",
                kMaxStages, io::format_number(s.wear.stage_hours).c_str(),
                reach > 1.0 ? (", its first history running to " + io::format_number(reach) + " x the last survey").c_str()
                            : "",
                io::format_number(hours[last]).c_str(), s.wear.stages, io::format_number(since_h).c_str(),
                io::format_number(std::ceil(since_h / kMaxStages)).c_str());
  throw InputError(file, "line " + std::to_string(measured.lines()[last]), buf);
}

void check_surveys_in_mill(const Measurements& measured, const Scene& scene, const std::string& file) {
  if (measured.areas_only) {
    if (measured.areas.losses) return;
    double smallest_m2 = INFINITY;
    for (int k = 0; k < scene.mill.kind_count(); ++k)
      smallest_m2 = std::min(smallest_m2, measure_profile(scene.mill.kind(k).points).area_m2);
    for (const AreaSurvey& s : measured.areas.surveys)
      if (s.value_m2 < kMinAreaShare * smallest_m2)
        throw InputError(file, "line " + std::to_string(s.line),
                         "a lifter area in mm^2, at least a thousandth of the scene's lifter (" +
                             io::format_number(in_mm2(smallest_m2)) + " mm^2); the survey at " +
                             io::format_number(s.hours) + " h gives " + io::format_number(in_mm2(s.value_m2)) +
                             " mm^2: is it in m^2?");
    return;
  }
  const double radius_m = scene.radius_m();
  const int rows = scene.mill.rows;
  if (rows <= 0) return;
  const double half_pitch_m = kPi * radius_m / rows;
  for (const Survey& s : measured.profiles)
    for (const Vec2& p : s.profile_m) {
      // Below the shell line no deeper than a measured surface may reach (a tenth of the
      // radius, far past any shell plate: a typo, or another origin).
      if (std::abs(p.x) <= 1.01 * half_pitch_m && p.y < radius_m && p.y >= -0.1 * radius_m) continue;
      char buf[400];
      std::snprintf(buf, sizeof buf,
                    "survey points within the lifter's liner unit, lifter-local mm: |x_mm| at most half the pitch "
                    "(%.1f mm), y_mm under the mill radius (%.1f mm) and at most a tenth of it (%.1f mm) below the "
                    "shell line; the survey at %g h has the point (%g, %g) mm",
                    in_mm(half_pitch_m), in_mm(radius_m), in_mm(0.1 * radius_m), s.hours, p.x * 1e3, p.y * 1e3);
      throw InputError(file, "line " + std::to_string(s.first_line), buf);
    }
}

std::vector<double> Measurements::hours() const {
  return areas_only ? survey_hours(areas) : survey_hours(profiles);
}

std::vector<std::size_t> Measurements::lines() const {
  std::vector<std::size_t> l;
  if (areas_only)
    for (const AreaSurvey& s : areas.surveys) l.push_back(s.line);
  else
    for (const Survey& s : profiles) l.push_back(s.first_line);
  return l;
}

Measurements parse_measurements(const std::string& text, const std::string& name) {
  const SurveyCsv csv = parse_survey_csv(text, name);
  const io::CsvData& d = csv.data;
  Measurements m;
  const bool points = d.has_column("x_mm") || d.has_column("y_mm");
  const bool areas = d.has_column("area_mm2") || d.has_column("area_loss_mm2");
  if (points && areas)
    throw InputError(name, "line " + std::to_string(csv.header_line),
                     std::string(kEitherFormat) + ", not both: this header has point and area columns");
  if (points) {
    m.profiles = parse_surveys(text, name);
  } else if (d.has_column("area_mm2") || d.has_column("area_loss_mm2")) {
    m.areas_only = true;
    m.areas = parse_area_surveys(text, name);
  } else {
    throw InputError(name, "line " + std::to_string(csv.header_line), kEitherFormat);
  }
  return m;
}

Measurements read_measurements(const std::string& path) { return parse_measurements(io::read_file(path), path); }

}  // namespace millwear::validation
