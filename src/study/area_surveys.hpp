#pragma once
// Measured lifter areas ("area surveys"): what a liner survey gives when only the lifters'
// cross-section areas were kept (from a profile gauge, a 3D scan or a weighed worn lifter),
// read from a CSV file; and a measurement file that holds either profiles or areas.
//
// Area survey file format (CSV, the same dialect and '#' comments as the profile surveys):
//   # liner survey, feed end, lifters 3 and 9
//   hours,area_mm2
//   0,43100             <- the new lifter (optional: the reference of the area loss; for a
//                          scene that starts worn, the row at its lifters.start_hours)
//   1500,37250          <- one row per lifter surveyed
//   1500,36900          <- several lifters at one inspection: one row each, same hours
//   3000,30100
// - hours: operating hours of the survey (>= 0); rows in any order, hours may repeat.
// - area_mm2: the lifter's metal cross-section above the original shell line, mm^2 (> 0),
//   the area `millwear profile` and OUT/summary.csv (area_mm2) report. Or, instead of
//   area_mm2, area_loss_mm2: the area lost since the history's start (the lifter new, or a
//   worn start's lifters.start_hours), mm^2 (finite; 0 in a row at that start).
// - Extra columns are ignored; at least one row.
// Area loss (what the calibration fits): for area_loss_mm2 the value itself (since the
// history's start); for area_mm2, A_ref - area, with A_ref the mean of the file's rows at the
// history's start (0 h, or a worn start's start_hours), or the scene's lifter area at that
// start when the file has none (then fitting the loss is fitting the area itself).
// Every problem throws InputError naming the file and the line.
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "study/surveys.hpp"

namespace millwear::validation {

struct AreaSurvey {
  double hours = 0.0;
  double value_m2 = 0.0;      // the lifter area, or the area loss (AreaSurveys::losses)
  std::size_t line = 0;       // 1-based line of the row (for messages)
};

struct AreaSurveys {
  bool losses = false;              // the file gave area_loss_mm2 instead of area_mm2
  std::vector<AreaSurvey> surveys;  // file order
};

AreaSurveys parse_area_surveys(const std::string& text, const std::string& name);

// The file text (mm^2, %.10g) with `comment` as '#' lines above the header.
std::string format_area_surveys(const AreaSurveys& surveys, const std::string& comment = "");

std::vector<double> survey_hours(const AreaSurveys& surveys);

// The measured areas and area losses of every row (file order), with the reference area
// of the losses (rules above); new_area_m2 is the scene's lifter area at the history's
// start, start_hours that start's operating hours.
struct MeasuredAreas {
  double reference_m2 = 0.0;
  bool reference_measured = false;   // from the file's rows at the start (not the scene)
  std::vector<double> area_m2, loss_m2;
};
MeasuredAreas measured_areas(const AreaSurveys& surveys, double new_area_m2, double start_hours);

// A wear rate can be fitted only to areas that shrink with operating time, and by less than
// the whole lifter: throws InputError(file, line of a survey, ...) if the area_loss_mm2 rows at
// the history's start do not average to 0 within kGainNoiseShare of the reference area (the
// loss counts from there; line of the first such row), if a survey's loss is not under
// the reference area, (line of the last survey) unless the area loss, fitted through the start,
// grows with the hours (sum of hours since the start x loss > 0), or if a survey after the
// start has more area than the reference area by over kGainNoiseShare of it (metal gained;
// kGainNoiseShare + kCastOverDrawingShare when that reference is the scene's lifter).
// one_shape = false (a pattern of lifters of other shapes): areas judged by the drawing are
// not checked for metal gained (a survey may be of any of the pattern's lifters).
void check_areas_shrink(const AreaSurveys& surveys, double new_area_m2, double start_hours, const std::string& file,
                        bool one_shape = true);

// A wear rate is fitted to the area lost, which must be told from a gauge's noise: throws
// InputError(file, line of the survey that lost the most, ...) unless a survey after the start
// lost more than kGainNoiseShare of the reference area. Calibration's check, after
// check_areas_shrink (validation compares surveys of any loss).
void check_area_losses_above_noise(const AreaSurveys& surveys, double new_area_m2, double start_hours,
                                   const std::string& file);

// A measurement file (`--measured`): profile surveys (columns x_mm and y_mm, surveys.hpp)
// or area surveys (area_mm2 or area_loss_mm2, no x_mm/y_mm), told apart by the header.
struct Measurements {
  bool areas_only = false;          // the file holds area surveys
  std::vector<Survey> profiles;     // when !areas_only
  AreaSurveys areas;                // when areas_only
  std::vector<double> hours() const;
  std::vector<std::size_t> lines() const;   // of each survey (its first row), for messages
  std::size_t count() const { return areas_only ? areas.surveys.size() : profiles.size(); }
};
Measurements parse_measurements(const std::string& text, const std::string& name);
Measurements read_measurements(const std::string& path);

// Surveys of the scene's lifter: throws InputError(file, line of the survey, ...) for a
// profile survey's point outside its liner unit (|x| over half the pitch at the shell, 1%
// allowed) or outside the mill (|y| at or over the radius), and for a surveyed area under a
// thousandth of the scene's smallest lifter (kMinAreaShare): a survey in other units (m for
// mm, m^2 for mm^2) or of another mill, which no fit could use.
void check_surveys_in_mill(const Measurements& measured, const Scene& scene, const std::string& file);
constexpr double kMinAreaShare = 1e-3;

// Every survey at or after the history's start (start_hours: `from`, e.g. the scene's
// lifters.start_hours): the wear before it is not simulated, so such a survey could be compared
// with nothing. Throws InputError(file, line of the first survey before it, ...).
void check_surveys_from_start(const Measurements& measured, double start_hours, const std::string& from,
                              const std::string& file);

// A fresh history reaches `reach` x the last survey's hours since the start in stages of the
// scene's stage_hours (or the surveys' common step, scene_for_survey_hours): at most kMaxStages
// of them (scene/limits.hpp), as a scene's own wear.stages. Throws InputError(file, line of the
// last survey, ...) naming the stages it needs and the stage_hours that would do.
void check_surveys_within_stages(const Measurements& measured, const Scene& scene, double reach,
                                 const std::string& file);

}  // namespace millwear::validation
