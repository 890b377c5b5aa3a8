#pragma once
// Lifter profiles: one lifter's cross-section in lifter-local coordinates (metres inside,
// millimetres in files). x runs along the shell (arc length) in the direction of rotation,
// so the leading face is at +x and the trailing face at -x; y runs radially inward from the
// shell surface. The polyline goes from the shell at the trailing foot to the shell at the
// leading foot, both feet at y = 0.
//
// A profile is a TOML file (a trapezoid or a polyline) or a measured profile, a CSV file
// x_mm,y_mm of points in order along the surface (a laser scan, a template gauge, a stage
// profile millwear wrote): see parse_measured_profile.
#include <string>
#include <vector>

#include "geometry/polyline.hpp"

namespace millwear {

enum class ProfileForm { Trapezoid, Polyline, Measured };

// Parameters of a parametric trapezoid (SI: metres, radians).
struct TrapezoidDef {
  double height_m = 0.0;
  double top_width_m = 0.0;
  double leading_face_angle_rad = 0.0;   // from the radial direction
  double trailing_face_angle_rad = 0.0;  // from the radial direction
};

struct LifterProfile {
  std::string name;
  std::string source_file;  // where it was read from (empty if built in code)
  // The profile files it read besides its own (match_area_of, and theirs), in reading order.
  std::vector<std::string> referenced_files;
  ProfileForm form = ProfileForm::Trapezoid;
  TrapezoidDef trapezoid;   // meaningful when form == Trapezoid
  Polyline points;          // lifter-local, m, trailing foot -> leading foot
  // Measured profiles only: the surface as measured (lifter-local, m), from the trailing
  // side to the leading side, repeated points dropped and loops cut out. Its ends lie at or
  // below the shell line, and it may take in the shell plates either side of the lifter;
  // `points` is then its lifter, the part above y = 0 around its highest point.
  Polyline measured;
  int dropped_points = 0;   // repeated points, and points of loops cut out, on reading
  // A measured profile with a comment line `# pitch_mm = P`: the scan is one whole liner
  // unit, its first and last points one pitch apart (the same place on neighbouring units),
  // and the mill's lifters must stand P apart. 0: not given (the scan is clipped to, or
  // continued along the shell out to, the mill's pitch).
  double unit_pitch_m = 0.0;
  int pitch_line = 0;       // the line of the file that gives it
};

// A whole liner unit's scan is its pitch wide, and that pitch the mill's, to within this
// share of the pitch (a gauge's placement; the same slack as a scan's overrun of the pitch).
constexpr double kPitchTolerance = 0.01;
// The largest loop cut out of a measured surface as a gauge's noise (points stepping back on
// a steep face), as a share of the lifter's area; a larger loop is points out of order.
constexpr double kMaxNoiseLoopShare = 0.01;
// 100 m bounds any point of a polyline profile or measured surface, in mm (a whole liner
// unit of the largest mill is under 2 m).
constexpr double kMaxPointMm = 1e5;
// The least a lifter's points (a profile, a scan, a survey) span across, in mm: a real
// lifter, new or worn down, is tens of millimetres or more wide, and points spanning less are
// metres written where millimetres belong.
constexpr double kMinSpanMm = 1.0;
// Throws InputError(file, where, ...) when the points span less than kMinSpanMm (in x and in
// y alike), saying what they span and that the file's unit is millimetres.
void check_points_span(const Polyline& points_m, const std::string& file, const std::string& where);

// Measured shape of a lifter polyline against a flat shell line y = 0 (lifter-local).
struct ProfileMetrics {
  double area_m2 = 0.0;            // cross-section area above y = 0
  double height_m = 0.0;           // largest y
  double base_width_m = 0.0;       // distance between the feet
  double top_width_m = 0.0;        // extent of the profile within 2% of height of the top
  double leading_face_angle_rad = 0.0;   // chord from leading foot to the face at mid-height
  double trailing_face_angle_rad = 0.0;  // chord from trailing foot to the face at mid-height
};

// Polyline of a trapezoid; the base is centred on x = 0.
Polyline trapezoid_points(const TrapezoidDef& t);
// Top width that gives the trapezoid the requested area (height and angles fixed).
// Throws InputError (file, key "match_area_of") if no positive top width does it.
double top_width_for_area(const TrapezoidDef& t, double area_m2, const std::string& file);

ProfileMetrics measure_profile(const Polyline& lifter_local);

// Read a profile file: TOML, or a measured profile when the name ends in .csv. Throws
// InputError naming the file, key (or line) and expectation. match_area_of is resolved
// relative to the file's folder.
LifterProfile load_profile(const std::string& path);

// A measured profile, CSV (io/csv.hpp's dialect: '#' comment lines, a byte-order mark, ';'
// with decimal commas and CRLF line ends are all read):
//   x_mm,y_mm        lifter-local mm, the coordinates of OUT/profiles/*.csv and of surveys
//   -40.0,-5.0       points in order along the surface (either direction), ends at or
//   ...              below the shell line y = 0; one lifter, or a whole liner unit
// Repeated points are dropped and loops (noise on a steep face) cut out; the lifter is the
// part above y = 0 around the highest point. A comment line `# pitch_mm = P` says the scan is
// one whole liner unit P mm wide: its points must span P (within kPitchTolerance), else the
// error names the file and the line. `name` names the file in errors.
LifterProfile parse_measured_profile(const std::string& text, const std::string& name);

// The lifter of a measured surface: from where it last rises through y = 0 before its
// highest point to where it first falls through it after. Throws InputError(file, key).
Polyline lifter_of_surface(const Polyline& surface, const std::string& file, const std::string& key);

// Check a lifter polyline: at least 3 points, feet on y = 0, trailing foot left of the
// leading foot, every other point above the shell, simple. Throws InputError.
void validate_lifter_polyline(const Polyline& pts, const std::string& file, const std::string& key);

// `profile --csv DIR`: each profile's polyline to DIR/<name>.csv, in mm. The check comes
// before anything is written: throws InputError when two profiles share a name (one file
// would overwrite the other), a target is one of the profiles' own input files, or a target
// exists and is not a file --csv wrote (its first line is not kProfileCsvHeader's).
void check_profile_csv_targets(const std::vector<LifterProfile>& profiles, const std::string& dir);
// The first line of every file write_profile_csvs writes (a comment: the file reads back as
// a measured profile).
constexpr const char* kProfileCsvHeader = "# written by millwear profile:";
// Creates DIR (InputError("", "--csv", ...) if it cannot) and writes each file atomically.
// Returns the files written.
std::vector<std::string> write_profile_csvs(const std::vector<LifterProfile>& profiles, const std::string& dir);

}  // namespace millwear
