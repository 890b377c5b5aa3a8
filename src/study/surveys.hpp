#pragma once
// Measured lifter profiles ("surveys"): what a mill's maintenance crew measures at a
// relining inspection, read from a CSV file.
//
// Survey file format (CSV, see io/csv.hpp for the dialect):
//   # Lines starting with '#' are comments (anywhere in the file; blank lines are skipped).
//   hours,x_mm,y_mm
//   0,-30.0,0.0          <- survey at 0 h (the new lifter), points in order along the profile
//   0,-16.5,0.0
//   ...
//   1500,-30.0,0.0       <- the next survey starts where the hours value changes
//   ...
// - hours: operating hours of the survey (>= 0). One block of consecutive rows per survey;
//   a block's hours value may not appear again later in the file.
// - x_mm, y_mm: lifter-local coordinates in mm (mill/mill.hpp): x along the shell from
//   the lifter centre, +x toward the leading face (forward rotation), y up from the
//   original shell line toward the mill axis. These are the coordinates of the profiles
//   `millwear run` writes (OUT/profiles/DESIGN_stageK.csv).
// - At least 2 points per survey, in order along the profile (either direction; a survey
//   running from +x to -x is reversed on reading). Extra columns are ignored.
// Every problem throws InputError naming the file and the line. A file of lifter areas only
// (hours,area_mm2) is read by area_surveys.hpp, which also tells the two formats apart.
#include <string>
#include <vector>

#include "geometry/polyline.hpp"
#include "io/csv.hpp"
#include "profiles/profile.hpp"

namespace millwear::validation {

// Metal a survey may show above the lifter it wore from (the survey at the history's start,
// or the scene's lifter there), as a share of that lifter's area: a gauge's noise, the share
// the readers already take as noise when they cut the loops of a survey or a scan. More is a
// gain of metal, which wear cannot make (a survey of another lifter, other units, or hours
// out of order): refused by check_areas_shrink (area files) and check_surveys_lose_metal
// (profile files, profile_fit.hpp).
constexpr double kGainNoiseShare = kMaxNoiseLoopShare;
// How much bigger than drawn a new lifter may be cast, as a share of the drawn lifter's area,
// allowed on top of kGainNoiseShare when the reference a survey is judged by is the drawing
// (the scene's lifter: no survey or area row at the history's start). A casting's dimensions
// are held to a per cent or two of the drawing (pattern allowances, foundry tolerance), so its
// section, the product of two of them, to a few per cent: 5% takes a casting about 2.5% over
// in both. A survey or area row at the start is the lifter as cast, the exact reference.
constexpr double kCastOverDrawingShare = 0.05;

struct Survey {
  double hours = 0.0;
  Polyline profile_m;          // lifter-local, metres, ordered from -x to +x
  std::size_t first_line = 0;  // 1-based line of the block's first row (for messages)
};

// Surveys in file order (blocks), each ordered from -x to +x. `name` names the file in
// errors. Throws InputError(name, "line N", ...).
std::vector<Survey> parse_surveys(const std::string& text, const std::string& name);

// The hours of every survey, in file order.
std::vector<double> survey_hours(const std::vector<Survey>& surveys);

// The file text for surveys (mm, %.10g), with `comment` (may be several lines) written as
// '#' lines above the header.
std::string format_surveys(const std::vector<Survey>& surveys, const std::string& comment = "");

// `comment` (may be several lines) as '#' lines, each ending in '\n'; "" for no comment.
std::string comment_lines(const std::string& comment);

// A measurement file read as CSV: '#' comment lines blanked, header names trimmed, and the
// header's own line in the file (1-based; comments may come before it). Shared by the
// profile and area survey readers.
struct SurveyCsv {
  io::CsvData data;
  std::size_t header_line = 1;
};
SurveyCsv parse_survey_csv(const std::string& text, const std::string& name);

using io::strip_comment_lines;  // io/csv.hpp

}  // namespace millwear::validation
