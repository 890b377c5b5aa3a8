// A plant's own liner as input: measured profiles (CSV), a history started from a worn liner,
// `run --continue`, lifter patterns (hi-lo) and a separate shell wear rate. Histories run the
// lab mill at draft fidelity with one or a few stages.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "common/errors.hpp"
#include "common/units.hpp"
#include "engine_fixtures.hpp"
#include "io/csv.hpp"
#include "io/run_folder.hpp"
#include "study/stage_files.hpp"
#include "temp_dir.hpp"
#include "wear/wear.hpp"

namespace fs = std::filesystem;

namespace millwear {
namespace {

using testing::source_path;

using testing::TempDir;

// The lab-mill scene with its [lifters] table replaced and `extra` lines appended to [wear]
// (absolute paths, so the scene can live anywhere).
std::string lab_scene_text(const std::string& lifters, const std::string& wear_extra = "", int stages = 2) {
  std::ifstream in(source_path("scenarios/lab-mill.toml"));
  std::ostringstream out;
  bool in_lifters = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("[", 0) == 0) in_lifters = line == "[lifters]";
    if (in_lifters) {
      if (line == "[lifters]") out << "[lifters]\n" << lifters << "\nshell_edge = 10.0\nlifter_edge = 2.0\n";
      continue;
    }
    if (line.rfind("stages = ", 0) == 0) line = "stages = " + std::to_string(stages);
    out << line << "\n";
    if (line == "[wear]") out << wear_extra;
  }
  return out.str();
}

// The lab lifter (20 mm high, or h_mm when worn, 10 mm top, 30/30 deg) as a scan: points every
// step_mm in x, a shell 5 mm below the original line out to 3 mm past the feet, Gaussian noise of
// sigma_mm on y, every tenth point written twice. Returns the file text; `repeats` counts the
// doubles.
std::string noisy_scan(double sigma_mm, int& repeats, unsigned seed = 7, double h_mm = 20.0, double step_mm = 0.5) {
  const double h = h_mm, top = 10.0, run = h * std::tan(30.0 * kPi / 180.0), hb = 0.5 * top + run;
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma_mm);
  std::string text = "# a laser scan: the lab lifter, shell 5 mm below its original line\nx_mm,y_mm\n";
  repeats = 0;
  char line[64];
  const auto points = static_cast<long>(std::lround((2.0 * hb + 6.0) / step_mm));
  for (long i = 0; i <= points; ++i) {
    const double x = -hb - 3.0 + static_cast<double>(i) * step_mm;
    const double ax = std::fabs(x);
    double y = ax <= 0.5 * top ? h : h * (hb - ax) / run;  // the face continues below the line
    y = std::max(y, -5.0) + noise(rng);
    std::snprintf(line, sizeof line, "%.3f,%.3f\n", x, y);
    text += line;
    if (i % 10 == 0) {
      text += line;
      ++repeats;
    }
  }
  return text;
}

std::string slurp(const fs::path& p) { return millwear::testing::read_text(p); }

// ---- measured profiles ----------------------------------------------------------------

TEST(MeasuredProfile, NoisyScanWithRepeatsGivesALifterWithFeetOnTheShell) {
  int repeats = 0;
  const LifterProfile p = parse_measured_profile(noisy_scan(0.5, repeats), "scan.csv");
  EXPECT_EQ(p.form, ProfileForm::Measured);
  EXPECT_GE(p.dropped_points, repeats);  // every repeat, and any loop the noise made
  EXPECT_DOUBLE_EQ(p.points.front().y, 0.0);
  EXPECT_DOUBLE_EQ(p.points.back().y, 0.0);
  EXPECT_LT(p.measured.front().y, -0.003);  // the worn shell stays in the surface
  // The trapezoid's area is 20 * (10 + 33.09) / 2 = 430.9 mm^2; noise of 0.5 mm over the
  // ~57 mm outline moves it by at most sigma x outline (28 mm^2).
  const double area_mm2 = measure_profile(p.points).area_m2 * 1e6;
  EXPECT_NEAR(area_mm2, 430.9, 0.5 * 57.0);
}

// A scan far denser than the mesh (56,000 points, a micrometre apart, with noise ten times the
// spacing) builds the liner a sparse scan of the same lifter builds: points thinned to an
// eighth of the lifter's edge (2 mm here), not a corner kept at every turn of the noise; the
// wear history starts from nearly the same lifter.
TEST(MeasuredProfile, ADenseScanMakesALinerAtTheMeshScale) {
  TempDir dir("millwear-liner-input-dense");
  int repeats = 0;
  dir.write("dense.csv", noisy_scan(0.01, repeats, 3, 20.0, 0.001));
  dir.write("sparse.csv", noisy_scan(0.0, repeats, 3, 20.0, 0.5));
  const std::string dense_file = dir.write("d.toml", lab_scene_text("rows = 12\nprofile = \"dense.csv\"", "", 1));
  const std::string sparse_file = dir.write("s.toml", lab_scene_text("rows = 12\nprofile = \"sparse.csv\"", "", 1));
  const Scene dense = load_scene(dense_file), sparse = load_scene(sparse_file);
  EXPECT_GT(dense.mill.kind(0).measured.size(), 10000u);  // the reader keeps the scan's detail
  ASSERT_NO_THROW(check_scene(dense, dense_file));
  const LinerUnit unit = new_liner_unit(dense, 0);
  const LinerUnit sparse_unit = new_liner_unit(sparse, 0);
  // The scan's 59 mm of surface at points at least 0.25 mm apart, and the shell beyond it.
  EXPECT_LT(unit.surface.size(), 59.0 / 0.25 + sparse_unit.surface.size());
  const double r = dense.radius_m();
  const double a_dense = measure_lifter(starting_unit(dense, 0, smoothing_radius(dense)), r).area_m2;
  const double a_sparse = measure_lifter(starting_unit(sparse, 0, smoothing_radius(sparse)), r).area_m2;
  EXPECT_NEAR(a_dense / a_sparse, 1.0, 0.01);
}

TEST(MeasuredProfile, SpreadsheetDialectsReadTheSamePoints) {
  const std::string plain = "x_mm,y_mm\n-20,-1\n-10,10\n0,12.5\n10,10\n20,-1\n";
  std::string semicolon = "x_mm;y_mm\n-20;-1\n-10;10\n0;12,5\n10;10\n20;-1\n";
  std::string crlf_bom = std::string(io::kUtf8Bom) + "# gauge 3\r\nx_mm,y_mm\r\n-20,-1\r\n-10,10\r\n0,12.5\r\n10,10\r\n20,-1\r\n";
  // Lines ended by a lone CR ("CSV (Macintosh)"), with a comment and the pitch line among them.
  std::string cr = "# gauge 3\r# pitch_mm = 40\rx_mm,y_mm\r-20,-1\r-10,10\r0,12.5\r10,10\r20,-1\r";
  const LifterProfile a = parse_measured_profile(plain, "a.csv");
  for (const std::string& text : {semicolon, crlf_bom, cr}) {
    const LifterProfile b = parse_measured_profile(text, "b.csv");
    ASSERT_EQ(a.measured.size(), b.measured.size());
    for (std::size_t i = 0; i < a.measured.size(); ++i) EXPECT_TRUE(a.measured[i] == b.measured[i]) << i;
  }
  EXPECT_DOUBLE_EQ(parse_measured_profile(cr, "cr.csv").unit_pitch_m, 0.04);
}

TEST(MeasuredProfile, ReversedScanIsTurnedRound) {
  const LifterProfile a = parse_measured_profile("x_mm,y_mm\n-20,0\n-10,10\n10,10\n20,0\n", "a.csv");
  const LifterProfile b = parse_measured_profile("x_mm,y_mm\n20,0\n10,10\n-10,10\n-20,0\n", "b.csv");
  EXPECT_DOUBLE_EQ(measure_profile(a.points).area_m2, measure_profile(b.points).area_m2);
  EXPECT_LT(b.points.front().x, b.points.back().x);
}

TEST(MeasuredProfile, BadScansAreRefusedNamingTheProblem) {
  auto message = [](const std::string& text) {
    try {
      parse_measured_profile(text, "s.csv");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(message("x_mm,y_mm\n-20,0\n0,10\n20,3\n").find("at or below the shell line"), std::string::npos);
  EXPECT_NE(message("x_mm,y_mm\n-20,0\n0,abc\n20,0\n").find("line 3"), std::string::npos);
  EXPECT_NE(message("x,y\n-20,0\n0,10\n20,0\n").find("x_mm"), std::string::npos);
  EXPECT_NE(message("x_mm,y_mm\n-20,-1\n0,-0.5\n20,-1\n").find("above the shell line"), std::string::npos);
  // A scan in metres (a 40 mm lifter written as 0.04) spans under a millimetre.
  EXPECT_NE(message("x_mm,y_mm\n-0.02,0\n-0.01,0.01\n0.01,0.01\n0.02,0\n")
                .find("x_mm,y_mm: millimetres, spanning at least 1 mm across as a lifter does; these points span 0.04 mm"),
            std::string::npos);
  // A lifter drawn as a closed polygon (the base back to the first point) is all loop.
  EXPECT_NE(message("x_mm,y_mm\n-20,0\n-10,20\n10,20\n20,0\n20,0\n-20,0\n").find("close on themselves"),
            std::string::npos);
  // A closed outline (the plates' underside drawn back to the start) and a surface drawn back
  // along its base cross nothing, or cross at no loop the reader cuts: refused at the point
  // beyond their ends, where `profile` took the first and `run` refused both with no place.
  const std::string outline = message("x_mm,y_mm\n-60,0\n-20,0\n-10,20\n5,20\n10,0\n60,0\n60,-1\n-60,-1\n");
  EXPECT_NE(outline.find("line 7: a surface from one side of the lifter to the other"), std::string::npos) << outline;
  EXPECT_NE(outline.find("x = 60 mm, lies 120 mm beyond both ends (x = -60 and -60 mm)"), std::string::npos) << outline;
  const std::string back = message("x_mm,y_mm\n-60,0\n-20,0\n-10,20\n5,20\n10,0\n60,0\n-60,0\n");
  EXPECT_NE(back.find("line 7: a surface from one side of the lifter to the other"), std::string::npos) << back;
  // A last reading a little back from the one before is still a scan.
  EXPECT_EQ(message("x_mm,y_mm\n-40,-1\n-16.5,0\n-5,20\n5,20\n16.5,0\n40,-1\n39.5,-1\n"), "accepted");
  // A second lifter in the scan would wear as shell plate.
  EXPECT_NE(message("x_mm,y_mm\n-40,-1\n-16.5,0\n-5,20\n5,20\n16.5,0\n23,-1\n23.5,0\n35,12\n45,12\n56.5,0\n75,-1\n")
                .find("one lifter per surface"),
            std::string::npos);
  // Gauge noise on plates at the line is shell, even beside a lifter worn to 6 mm (noise of a
  // tenth of its height).
  EXPECT_EQ(message("x_mm,y_mm\n-40,-1\n-30,0.5\n-16.5,0\n-5,20\n5,20\n16.5,0\n30,0.5\n40,-1\n"), "accepted");
  EXPECT_EQ(message("x_mm,y_mm\n-40,-0.3\n-35,-0.5\n-30,0.7\n-25,-0.2\n-16.5,0\n-5,6\n5,6\n16.5,0\n25,0.6\n"
                    "30,-0.4\n40,-0.2\n"),
            "accepted");
  // A point a hair above the line on a shallow edge is the foot itself, not a crossing
  // extrapolated outside the scan.
  const LifterProfile shallow = parse_measured_profile("x_mm,y_mm\n-30,-1\n-20,0.0009\n-19,0.0012\n-10,20\n10,20\n20,-1\n", "f.csv");
  EXPECT_GE(shallow.points.front().x, -0.020);
  // A measured profile is named after its file, which has no name key to give.
  try {
    parse_measured_profile("x_mm,y_mm\n-20,-1\n-10,10\n10,10\n20,-1\n", "Mill 3 scan.csv");
    ADD_FAILURE() << "a name with spaces was taken";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("rename the file"), std::string::npos) << e.what();
  }
}

TEST(MeasuredProfile, SceneRefusesAScanWiderThanThePitch) {
  TempDir dir("millwear-liner-input-wide");
  // The lab mill's pitch is 157 mm: a scan 300 mm wide cannot be one liner unit.
  dir.write("wide.csv", "x_mm,y_mm\n-150,0\n-10,0\n-5,15\n5,15\n10,0\n150,0\n");
  const std::string scene = dir.write("s.toml", lab_scene_text("rows = 12\nprofile = \"wide.csv\""));
  try {
    load_scene(scene);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "lifters.rows");
    EXPECT_NE(std::string(e.what()).find("no wider than the pitch"), std::string::npos);
  }
}

// A scan of one lifter is in lifter-local coordinates, as the surveys compared with its
// history are: x_mm = 0 on the lifter's centre line. It is taken as measured, not moved, so
// scan and surveys stay in one frame: a lifter whose feet are off x = 0 (a worn face moves its
// foot) keeps them there. Refused, naming the scan, its feet and that x = 0 must be the
// lifter's centre line, is only a scan whose lifter cannot stand in its row about x = 0: x = 0
// outside its metal, or a lifter wider than the pitch about x = 0 that would fit centred.
TEST(MeasuredProfile, AScanIsTakenInTheSurveysFrameUnlessItsLifterCannotStandInItsRow) {
  TempDir dir("millwear-liner-input-off-centre");
  const auto scan = [](double offset_mm, double hb, double top) {
    char buf[256];
    std::snprintf(buf, sizeof buf, "x_mm,y_mm\n%.4f,-2\n%.4f,0\n%.4f,20\n%.4f,20\n%.4f,0\n%.4f,-2\n",
                  offset_mm - hb - 8.0, offset_mm - hb, offset_mm - top, offset_mm + top, offset_mm + hb,
                  offset_mm + hb + 8.0);
    return std::string(buf);
  };
  const double lab_hb = 5.0 + 20.0 * std::tan(30.0 * kPi / 180.0);  // the lab lifter's half base
  const auto scene_of = [&](const std::string& text) {
    dir.write("scan.csv", text);
    return load_scene(dir.write("s.toml", lab_scene_text("rows = 12\nprofile = \"scan.csv\"")));
  };
  // 8 mm off: taken, and the liner unit keeps the scan where it is (its top from 3 to 13 mm).
  for (double taken : {0.0, 8.0, -12.0}) {
    const Scene s = scene_of(scan(taken, lab_hb, 5.0));
    const LinerUnit u = new_liner_unit(s);
    double top_left = 1.0, top_right = -1.0;
    for (const Vec2& p : u.surface)
      if (p.y > 0.0199) top_left = std::min(top_left, p.x), top_right = std::max(top_right, p.x);
    EXPECT_NEAR(top_left * 1e3, taken - 5.0, 1e-6) << taken;
    EXPECT_NEAR(top_right * 1e3, taken + 5.0, 1e-6) << taken;
  }
  const auto refusal = [&](const std::string& text) {
    try {
      scene_of(text);
    } catch (const InputError& e) {
      EXPECT_EQ(e.file, (dir.path() / "scan.csv").string());
      EXPECT_EQ(e.where, "x_mm");
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  // 20 mm off: x = 0 is beside the lifter (its feet at 3.453 and 36.547 mm).
  std::string m = refusal(scan(20.0, lab_hb, 5.0));
  EXPECT_NE(m.find("x_mm = 0 on the lifter's centre line, as in the surveys"), std::string::npos) << m;
  EXPECT_NE(m.find("its feet are at x = 3.453 and 36.547 mm, and x = 0 is outside its metal"), std::string::npos) << m;
  EXPECT_NE(m.find("lifters.profile"), std::string::npos) << m;
  // A lifter 120 mm wide at its base fits the 157 mm pitch centred, not 30 mm off: about x = 0
  // it reaches 90 mm, past the half pitch (78.5 mm).
  EXPECT_EQ(refusal(scan(0.0, 60.0, 20.0)), "accepted");
  m = refusal(scan(30.0, 60.0, 20.0));
  EXPECT_NE(m.find("about x = 0 it reaches 90 mm to one side, past half the pitch"), std::string::npos) << m;
}

// A whole liner unit's scan with its pitch: the lab lifter (base +-16.55 mm) in the 157.08 mm
// pitch of 12 rows in the 0.6 m mill, the shell plate between lifters worn into a dish 4 mm
// deep, the scan starting 50 mm left of the lifter's centre and ending one pitch later.
double lab_pitch_mm() { return 2.0 * kPi * 300.0 / 12.0; }
double lab_unit_y(double x_mm) {  // the true surface, periodic in the pitch
  const double p = lab_pitch_mm(), hb = 5.0 + 20.0 * std::tan(30.0 * kPi / 180.0);  // half base 16.55
  double x = std::fmod(x_mm, p);
  if (x > 0.5 * p) x -= p;
  if (x < -0.5 * p) x += p;
  const double ax = std::fabs(x);
  if (ax <= 5.0) return 20.0;
  if (ax <= hb) return 20.0 * (hb - ax) / (hb - 5.0);
  return -4.0 * std::sin(kPi * (ax - hb) / (p - 2.0 * hb));  // the dish, 0 at both lifters
}
std::string whole_unit_scan(const std::string& pitch_line) {
  std::string text = "# a template gauge of one liner unit\n" + pitch_line + "x_mm,y_mm\n";
  char line[64];
  const double a = -50.0, p = lab_pitch_mm();
  const int n = 400;
  for (int i = 0; i <= n; ++i) {
    const double x = a + p * i / n;
    std::snprintf(line, sizeof line, "%.6f,%.6f\n", x, lab_unit_y(x));
    text += line;
  }
  return text;
}

TEST(MeasuredProfile, PitchLineMakesTheScanAWholeUnitCheckedAgainstItsPointsAndTheMill) {
  TempDir dir("millwear-liner-input-pitch");
  char pitch[64];
  std::snprintf(pitch, sizeof pitch, "# pitch_mm = %.3f\n", lab_pitch_mm());
  const LifterProfile p = parse_measured_profile(whole_unit_scan(pitch), "unit.csv");
  EXPECT_NEAR(p.unit_pitch_m * 1e3, lab_pitch_mm(), 1e-3);
  EXPECT_EQ(p.pitch_line, 2);

  // In the mill the unit is the scan repeated one pitch on: left of where the scan starts
  // (x < -50 mm) the surface is the dish the scan measured right of the lifter.
  dir.write("unit.csv", whole_unit_scan(pitch));
  const Scene with = load_scene(dir.write("with.toml", lab_scene_text("rows = 12\nprofile = \"unit.csv\"")));
  auto y_at = [](const LinerUnit& u, double x_mm) {
    for (std::size_t i = 0; i + 1 < u.surface.size(); ++i) {
      const Vec2 a = u.surface[i] * 1e3, b = u.surface[i + 1] * 1e3;
      if ((a.x - x_mm) * (b.x - x_mm) <= 0.0 && a.x != b.x) return a.y + (b.y - a.y) * (x_mm - a.x) / (b.x - a.x);
    }
    return std::nan("");
  };
  const LinerUnit uw = new_liner_unit(with);
  const double half = 0.5 * lab_pitch_mm() * 1e-3;
  EXPECT_NEAR(uw.surface.front().x, -half, 1e-12);
  EXPECT_NEAR(uw.surface.back().x, half, 1e-12);
  // The unit is centred on the lifter's feet as read (where the scan's chords cross y = 0,
  // a little off the true feet): unit x is scan x + shift. A measured unit is resampled at the
  // 2 mm lifter edge: on the dish, 4 mm deep over 124 mm, chords stay within
  // (2 mm)^2 / 8 x its curvature 4 (pi / 124 mm)^2 = 0.0013 mm of the curve.
  const double shift_mm = -0.5 * (p.points.front().x + p.points.back().x) * 1e3;
  EXPECT_LT(std::fabs(shift_mm), 0.4);  // within a scan step (0.39 mm) of the true centre
  for (double x : {-75.0, -65.0, -55.0, -40.0, 30.0, 60.0, 75.0})
    EXPECT_NEAR(y_at(uw, x), lab_unit_y(x - shift_mm), 0.002) << x;
  // Without the line the scan is taken for one lifter with its plates, centred on the lifter:
  // reaching 107 mm right of it, past the half pitch (78.5 mm), it is refused.
  dir.write("plain.csv", whole_unit_scan(""));
  try {
    load_scene(dir.write("without.toml", lab_scene_text("rows = 12\nprofile = \"plain.csv\"")));
    ADD_FAILURE() << "a scan wider than the pitch about its lifter was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no wider than the pitch"), std::string::npos) << e.what();
  }

  // A pitch its points do not span: the file and the pitch line named.
  auto message = [](const std::function<void()>& f) {
    try {
      f();
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  std::string m = message([] { parse_measured_profile(whole_unit_scan("# pitch_mm = 140\n"), "short.csv"); });
  EXPECT_NE(m.find("short.csv"), std::string::npos) << m;
  EXPECT_NE(m.find("line 2"), std::string::npos) << m;
  EXPECT_NE(m.find("pitch_mm = 140"), std::string::npos) << m;
  m = message([] { parse_measured_profile(whole_unit_scan("# pitch_mm = wide\n"), "bad.csv"); });
  EXPECT_NE(m.find("line 2"), std::string::npos) << m;
  // A near miss (a colon for the '=', another case) is refused as a pitch line written wrong,
  // where it read as a comment and the whole unit as one lifter with its plates.
  m = message([] { parse_measured_profile(whole_unit_scan("# pitch_mm: 157.08\n"), "near.csv"); });
  EXPECT_NE(m.find("near.csv: line 2"), std::string::npos) << m;
  EXPECT_NE(m.find("'# pitch_mm = P'"), std::string::npos) << m;
  for (const char* line : {"# Pitch_mm = 157.08\n", "# PITCH_MM=157.08\n"})
    EXPECT_NEAR(parse_measured_profile(whole_unit_scan(line), "case.csv").unit_pitch_m * 1e3, lab_pitch_mm(), 0.01) << line;
  // Ends at two heights cannot repeat round the mill: the step is named, not a crossing.
  m = message([&] {
    std::string text = whole_unit_scan(pitch);
    const std::size_t last = text.rfind(',', text.size() - 2);
    text = text.substr(0, last) + ",-10\n";  // the last point 10 mm below the first
    parse_measured_profile(text, "step.csv");
  });
  EXPECT_NE(m.find("step.csv: line 2"), std::string::npos) << m;
  EXPECT_NE(m.find("at one height"), std::string::npos) << m;
  // Agreeing with its points but not with the mill: 10 rows stand 188.5 mm apart.
  const std::string ten = dir.write("ten.toml", lab_scene_text("rows = 10\nprofile = \"unit.csv\""));
  m = message([&] { load_scene(ten); });
  EXPECT_NE(m.find("unit.csv"), std::string::npos) << m;
  EXPECT_NE(m.find("line 2"), std::string::npos) << m;
  EXPECT_NE(m.find("188.496"), std::string::npos) << m;
  // The same through the command line: exit 2 before any work.
  const auto r = millwear::testing::run_millwear("run " + millwear::testing::quoted(ten) + " -o " +
                                                 millwear::testing::quoted(dir.path() / "out"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("line 2"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir.path() / "out"));
}

// The noisy scan at 2000 h: the history starts there, its stage 0 is the file's lifter
// re-smoothed (area within the reported change), later stages are valid profiles again.
// A worn lifter scanned with gauge noise starts from its scan re-smoothed: whatever the draw,
// the noise the first pass takes is not refused. A scan of a fin thinner than the particles,
// which the first pass all but removes, is, naming the file.
TEST(WornStart, NoisyScansOfAWornLifterAreTakenAndAFinIsRefused) {
  TempDir dir("millwear-liner-input-worn-noise");
  for (unsigned seed = 1; seed <= 10; ++seed) {
    int repeats = 0;
    dir.write("scan.csv", noisy_scan(0.5, repeats, seed, 8.0));
    const std::string scene_file =
        dir.write("s.toml", lab_scene_text("rows = 12\nprofile = \"scan.csv\"\nstart_hours = 2000", "", 1));
    const Scene scene = load_scene(scene_file);
    EXPECT_NO_THROW(check_scene(scene, scene_file)) << "seed " << seed;
  }
  const std::string fin = dir.write("fin.csv", "x_mm,y_mm\n-20,-1\n-0.1,0\n0,20\n0.1,0\n20,-1\n");
  const std::string fin_scene = dir.write("f.toml", lab_scene_text("rows = 12\nprofile = \"fin.csv\"", "", 1));
  try {
    check_scene(load_scene(fin_scene), fin_scene);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file, fin);
    EXPECT_EQ(e.where, "x_mm,y_mm");
  }
}

// The history starts from the scan re-smoothed, a little lower than the scan's highest point:
// a replacement height between the two is refused before any work (its life would have
// ended before the history began).
TEST(WornStart, AReplacementHeightAboveTheReSmoothedLifterIsRefused) {
  const std::string file = source_path("scenarios/lab-worn-start.toml");
  const Scene scene = load_scene(file);
  const double start_m = measure_lifter(starting_unit(scene, 0, smoothing_radius(scene)), scene.radius_m()).height_m;
  double scan_top_m = 0.0;
  for (const Vec2& p : scene.mill.kind(0).measured) scan_top_m = std::max(scan_top_m, p.y);
  ASSERT_LT(start_m, scan_top_m);  // what the scene reader alone cannot see
  const auto with_height = [&](double m) {
    return load_scene(file, {"wear.replacement_height=" + io::format_number(m * 1e3)});
  };
  try {
    check_scene(with_height(0.5 * (start_m + scan_top_m)), file);
    ADD_FAILURE() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "wear.replacement_height");
    EXPECT_NE(std::string(e.what()).find("re-smoothed"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(check_scene(with_height(start_m - 1e-4), file));
}

TEST(WornStart, NoisyScanRunsFromItsHoursAndItsStageProfilesReadBack) {
  TempDir dir("millwear-liner-input-worn");
  int repeats = 0;
  const std::string scan = dir.write("survey-2000h.csv", noisy_scan(0.5, repeats));
  const std::string scene_file =
      dir.write("s.toml", lab_scene_text("rows = 12\nprofile = \"survey-2000h.csv\"\nstart_hours = 2000", "", 1));
  const Scene scene = load_scene(scene_file);
  const WearHistory h = run_wear_history(scene);
  ASSERT_TRUE(h.failure.empty()) << h.failure;
  ASSERT_EQ(h.stages.size(), 2u);
  EXPECT_DOUBLE_EQ(h.stages[0].hours, 2000.0);
  EXPECT_DOUBLE_EQ(h.stages[1].hours, 2100.0);
  EXPECT_DOUBLE_EQ(h.start_hours, 2000.0);
  EXPECT_GT(h.life_h, 2100.0);  // counted on the survey's clock

  // The file's own lifter area, measured as the mill measures a unit (polar map), on the
  // points as written.
  const LifterProfile p = load_profile(scan);
  const LinerUnit built = new_liner_unit(scene);
  LinerUnit as_read;
  as_read.lifter_half_base_m = built.lifter_half_base_m;
  const double shift = -0.5 * (p.points.front().x + p.points.back().x);
  for (const Vec2& q : p.measured) as_read.surface.push_back({q.x + shift, q.y});
  const double a_file = measure_lifter(as_read, scene.radius_m()).area_m2 * 1e6;
  // The reported change: "... went from A mm^2 (the file's) to B mm^2 (C mm^2, ...".
  ASSERT_FALSE(h.events.empty());
  const std::string& note = h.events.front();
  double from = 0, to = 0, change = 0;
  const auto at = note.find("went from ");
  ASSERT_NE(at, std::string::npos) << note;
  ASSERT_EQ(std::sscanf(note.c_str() + at, "went from %lf mm^2 (the file's) to %lf mm^2 (%lf", &from, &to, &change), 3)
      << note;
  const double a0 = h.stages[0].lifter.area_m2 * 1e6;
  // Printed to 6 significant digits: equal to that precision.
  EXPECT_NEAR(from, a_file, 1e-5 * a_file);
  EXPECT_NEAR(to, a0, 1e-5 * a0);
  EXPECT_LE(std::fabs(a0 - a_file), std::fabs(change) + 1e-5 * a0);
  // Re-smoothing takes the noise, not the lifter: at most sigma x the ~57 mm outline.
  EXPECT_LT(std::fabs(change), 0.5 * 57.0);
  EXPECT_LT(h.stages[1].lifter.area_m2, h.stages[0].lifter.area_m2);

  // Round trip: each stage profile as a scene's profile gives the stage's metrics (0.1%).
  for (const StageRecord& rec : h.stages) {
    study::write_profile_csv(dir.path().string(), "trip", rec);
    const std::string csv = io::profile_path(dir.path().string(), "trip", rec.stage);
    const Scene again = load_scene(
        dir.write("again.toml", lab_scene_text("rows = 12\nprofile = \"" + csv + "\"", "", 1)));
    const LifterMetrics m = measure_lifter(new_liner_unit(again), again.radius_m());
    EXPECT_NEAR(m.area_m2, rec.lifter.area_m2, 1e-3 * rec.lifter.area_m2) << "stage " << rec.stage;
    EXPECT_NEAR(m.height_m, rec.lifter.height_m, 1e-3 * rec.lifter.height_m) << "stage " << rec.stage;
  }
}

// ---- patterns and shell rate ---------------------------------------------------------

TEST(Pattern, RowsOfAKindAreAveragedTogether) {
  TempDir dir("millwear-liner-input-avg");
  const std::string lab = source_path("profiles/lab-2x30.toml");
  dir.write("lo.toml", "name = \"lab-lo\"\nform = \"trapezoid\"\nheight = 12.0\ntop_width = 10.0\n"
                      "leading_face_angle = 30.0\ntrailing_face_angle = 30.0\n");
  const Scene s = load_scene(dir.write(
      "s.toml", lab_scene_text("rows = 12\npattern = [\"" + lab + "\", \"lo.toml\"]")));
  const MillGeometry mill = build_scene_mill(s);
  ASSERT_EQ(mill.kinds, 2);
  ASSERT_EQ(mill.units.size(), 2u);
  EXPECT_NE(mill.units[0].surface.size(), mill.units[1].surface.size());
  // Work equal to the row number on every edge: kind 0 averages rows 0, 2, ..., 10 (5),
  // kind 1 rows 1, 3, ..., 11 (6).
  std::vector<double> work(mill.edges.size());
  for (std::size_t e = 0; e < work.size(); ++e) work[e] = mill.edges[e].row;
  const auto per_unit = unit_edge_work(mill, work, true);
  ASSERT_EQ(per_unit.size(), 2u);
  for (double w : per_unit[0]) EXPECT_NEAR(w, 5.0, 1e-12);
  for (double w : per_unit[1]) EXPECT_NEAR(w, 6.0, 1e-12);
}

TEST(Pattern, BadPatternsAreRefused) {
  TempDir dir("millwear-liner-input-bad");
  const std::string lab = source_path("profiles/lab-2x30.toml");
  auto where = [&](const std::string& lifters) {
    try {
      load_scene(dir.write("s.toml", lab_scene_text(lifters)));
    } catch (const InputError& e) {
      return e.where;
    }
    return std::string("accepted");
  };
  EXPECT_EQ(where("rows = 12\npattern = [\"" + lab + "\", \"" + lab + "\", \"" + lab + "\", \"" + lab + "\", \"" +
                  lab + "\"]"),
            "lifters.rows");  // 12 rows do not take a pattern of 5
  EXPECT_EQ(where("rows = 12\nprofile = \"" + lab + "\"\npattern = [\"" + lab + "\"]"), "lifters.pattern");
  EXPECT_EQ(where("rows = 12\npattern = [\"" + lab + "\", 3]"), "lifters.pattern[1]");
  EXPECT_EQ(where("rows = 12\npattern = [\"" + lab + "\", \"missing.toml\"]"), "lifters.pattern[1]");
  // A kind too tall for the mill: the key of that kind, not lifters.profile.
  const std::string tall = dir.write("tall.toml", "name = \"tall\"\nform = \"trapezoid\"\nheight = 160.0\ntop_width = 10.0\n"
                                                 "leading_face_angle = 10.0\ntrailing_face_angle = 10.0\n");
  EXPECT_EQ(where("rows = 12\npattern = [\"" + lab + "\", \"" + tall + "\"]"), "lifters.pattern[1]");
}

// Kinds are told apart by their profiles' names in every output: two profiles of other
// shapes under one name are refused, naming the later key and the name; the same profile
// twice is one kind repeated (Pattern.TwoIdenticalKindsEqualThePlainLiner) and is taken.
TEST(Pattern, KindsOfOtherShapesUnderOneNameAreRefused) {
  TempDir dir("millwear-liner-input-same-name");
  const std::string lab = source_path("profiles/lab-2x30.toml");
  dir.write("low.toml", "name = \"lab-2x30\"\nform = \"trapezoid\"\nheight = 12.0\ntop_width = 10.0\n"
                        "leading_face_angle = 30.0\ntrailing_face_angle = 30.0\n");
  try {
    load_scene(dir.write("s.toml", lab_scene_text("rows = 12\npattern = [\"" + lab + "\", \"low.toml\"]")));
    ADD_FAILURE() << "two kinds named lab-2x30 were accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "lifters.pattern[1]");
    const std::string m = e.what();
    EXPECT_NE(m.find("the profile named 'lab-2x30' here is of other points than the one of that name in "
                     "lifters.pattern[0]"),
              std::string::npos)
        << m;
  }
  const Scene twice = load_scene(dir.write("t.toml", lab_scene_text("rows = 12\npattern = [\"" + lab + "\", \"" + lab + "\"]")));
  EXPECT_EQ(twice.mill.kind_count(), 2);
  // Two scans of one file name in two folders: a scan is named by its file, so the advice is
  // to rename one.
  const std::string scan = "x_mm,y_mm\n-30,-3\n-25,-2.5\n-20,-1\n-16.55,0\n-12,7\n-5,17\n0,16.5\n4,13\n8,6\n"
                           "10.5,0.5\n11.5,-1.5\n15,-3\n25,-3\n30,-3\n";
  std::string other = scan;
  other.replace(other.find("-5,17"), 5, "-5,16");
  std::filesystem::create_directories(dir.path() / "a");
  std::filesystem::create_directories(dir.path() / "b");
  dir.write("a/scan.csv", scan);
  dir.write("b/scan.csv", other);
  try {
    load_scene(dir.write("u.toml", lab_scene_text("rows = 12\npattern = [\"a/scan.csv\", \"b/scan.csv\"]")));
    ADD_FAILURE() << "two scans named scan of other points were accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("a scan is named by its file: rename one of the files"), std::string::npos)
        << e.what();
  }
}

TEST(ShellWearRate, ShellEdgesWearAtTheirOwnRate) {
  const Scene s = testing::lab_mill();
  const LinerUnit unit = new_liner_unit(s);
  const std::size_t n = unit.surface.size() - 1;
  const std::vector<double> work(n, 2.0), len(n, 0.01);
  // A dh = C dw on every edge, lifter edges at C = 1e-9 m^3/J, shell edges at 4e-9.
  const auto d = edge_depths(unit, work, len, 0.0, 0.025, 1e-9, true, 4e-9);
  for (std::size_t j = 0; j < n; ++j)
    EXPECT_DOUBLE_EQ(d[j], is_lifter_edge(unit, static_cast<int>(j)) ? archard_depth_m(2.0, 0.01, 0.025, 1e-9)
                                                                      : archard_depth_m(2.0, 0.01, 0.025, 4e-9));
}

// Two identical kinds are the plain liner: the same geometry gives the same charge (stage 0
// bit for bit), and each kind's wear is the plain liner's within the window's statistics.
TEST(Pattern, TwoIdenticalKindsEqualThePlainLiner) {
  TempDir dir("millwear-liner-input-same");
  const std::string lab = source_path("profiles/lab-2x30.toml");
  const Scene plain = load_scene(dir.write("plain.toml", lab_scene_text("rows = 12\nprofile = \"" + lab + "\"", "", 1)));
  const Scene twice = load_scene(
      dir.write("twice.toml", lab_scene_text("rows = 12\npattern = [\"" + lab + "\", \"" + lab + "\"]", "", 1)));
  const WearHistory a = run_wear_history(plain), b = run_wear_history(twice);
  ASSERT_EQ(a.stages.size(), 2u);
  ASSERT_EQ(b.stages.size(), 2u);
  EXPECT_EQ(a.stages[0].charge.power_kW_per_m, b.stages[0].charge.power_kW_per_m);
  ASSERT_EQ(b.stages[0].kind_area_loss_rate_m2_per_s.size(), 2u);
  // The plain rate is the mean over all 12 rows, each kind's over 6 of them: the mean of the
  // two kinds' rates is the plain rate (to rounding).
  const double plain_rate = a.stages[0].area_loss_rate_m2_per_s;
  const double k0 = b.stages[0].kind_area_loss_rate_m2_per_s[0], k1 = b.stages[0].kind_area_loss_rate_m2_per_s[1];
  EXPECT_NEAR(0.5 * (k0 + k1), plain_rate, 1e-9 * plain_rate);
  // After a stage of wear each kind has lost what the plain liner lost, within the
  // statistics: a kind's rate differs from the plain one by (k0 - k1) / 2, whose standard
  // error is the plain rate's (half the rows, sqrt 2 the error, halved); 4 of them.
  const double sem = a.stages[0].area_loss_rate_rel_sem * plain_rate;
  const double lost_plain = a.stages[0].lifter.area_m2 - a.stages[1].lifter.area_m2;
  const double hours_s = (a.stages[1].hours - a.stages[0].hours) * kSecondsPerHour;
  for (std::size_t k = 0; k < 2; ++k) {
    const double lost = b.stages[0].kinds[k].area_m2 - b.stages[1].kinds[k].area_m2;
    EXPECT_NEAR(lost, lost_plain, 4.0 * sem * hours_s) << "kind " << k;
  }
}

// A hi-lo liner on the lab mill: the high lifters take the charge's lift and lose more area
// per hour than the low ones; each kind's life is reported.
TEST(Pattern, HighLiftersWearFasterThanLowOnes) {
  TempDir dir("millwear-liner-input-hilo");
  const std::string lab = source_path("profiles/lab-2x30.toml");
  dir.write("lo.toml", "name = \"lab-lo\"\nform = \"trapezoid\"\nheight = 12.0\ntop_width = 10.0\n"
                      "leading_face_angle = 30.0\ntrailing_face_angle = 30.0\n");
  const Scene s = load_scene(
      dir.write("s.toml", lab_scene_text("rows = 12\npattern = [\"" + lab + "\", \"lo.toml\"]", "", 1)));
  const WearHistory h = run_wear_history(s);
  ASSERT_TRUE(h.failure.empty()) << h.failure;
  const StageRecord& r = h.stages[0];
  ASSERT_EQ(r.kind_area_loss_rate_m2_per_s.size(), 2u);
  EXPECT_GT(r.kind_area_loss_rate_m2_per_s[0], r.kind_area_loss_rate_m2_per_s[1]);
  EXPECT_GT(r.kinds[0].height_m, r.kinds[1].height_m);
  ASSERT_EQ(h.kind_life_h.size(), 2u);
  for (double life : h.kind_life_h) EXPECT_GT(life, 0.0);
}

// summary.csv of a hi-lo run: every kind's lifter on each stage's row (the figures of
// kinds.csv, read without joining files), the liner's life that of the kind that reaches the
// replacement height first, and the kinds figure.
// The lab mill with a pattern of its 2x30 lifter and a 12 mm low trapezoid, run one stage
// into DIR/out with `extra` options; returns the output folder.
namespace {

fs::path run_hilo_lab(const TempDir& dir, const std::string& extra) {
  const std::string lab = source_path("profiles/lab-2x30.toml");
  dir.write("lo.toml", "name = \"lab-lo\"\nform = \"trapezoid\"\nheight = 12.0\ntop_width = 10.0\n"
                      "leading_face_angle = 30.0\ntrailing_face_angle = 30.0\n");
  const std::string scene =
      dir.write("s.toml", lab_scene_text("rows = 12\npattern = [\"" + lab + "\", \"lo.toml\"]", "", 1));
  const fs::path out = dir.path() / "out";
  const auto r = millwear::testing::run_millwear("run " + millwear::testing::quoted(scene) + " -o " +
                                                 millwear::testing::quoted(out) + " -q" + extra);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  return out;
}

}  // namespace

TEST(Pattern, SummaryCarriesEveryKindAndTheLinerLife) {
  TempDir dir("millwear-liner-input-hilo-summary");
  const fs::path out = run_hilo_lab(dir, "");
  ASSERT_FALSE(::testing::Test::HasFailure());
  const io::CsvData sum = io::read_csv((out / "summary.csv").string());
  const io::CsvData kinds = io::read_csv((out / "kinds.csv").string());
  ASSERT_EQ(sum.row_count(), 2u);  // stages 0 and 1
  ASSERT_EQ(kinds.row_count(), 4u);  // 2 kinds x 2 stages
  for (const char* c : {"kind0_profile", "kind0_area_mm2", "kind0_area_loss_pct", "kind0_height_mm",
                        "kind0_area_loss_rate_mm2_per_1000h", "kind0_life_h", "kind0_life_extrapolated",
                        "kind1_profile", "kind1_area_mm2", "kind1_life_h"})
    EXPECT_TRUE(sum.has_column(c)) << c;
  EXPECT_FALSE(sum.has_column("kind2_area_mm2"));
  for (std::size_t i = 0; i < kinds.row_count(); ++i) {
    const int k = static_cast<int>(kinds.number(i, "kind"));
    const std::size_t row = static_cast<std::size_t>(kinds.number(i, "stage"));
    const std::string pre = "kind" + std::to_string(k) + "_";
    EXPECT_EQ(sum.text(row, sum.column(pre + "profile")), kinds.text(i, kinds.column("profile")));
    // Both files are written from the same doubles to the same 10 digits: equal as text.
    for (const char* c : {"area_mm2", "area_loss_pct", "height_mm", "area_loss_rate_mm2_per_1000h", "life_h",
                          "life_extrapolated"})
      EXPECT_EQ(sum.text(row, sum.column(pre + c)), kinds.text(i, kinds.column(c))) << pre << c;
  }
  // The first kind's columns are the plain ones; the liner's life is the shorter-lived kind's.
  EXPECT_EQ(sum.text(1, sum.column("area_mm2")), sum.text(1, sum.column("kind0_area_mm2")));
  EXPECT_EQ(sum.text(0, sum.column("kind1_profile")), "lab-lo");
  const double l0 = sum.number(0, "kind0_life_h"), l1 = sum.number(0, "kind1_life_h");
  EXPECT_EQ(sum.number(0, "life_h"), std::min(l0, l1));
  EXPECT_NE(l0, l1);
  // The kinds figure (with gnuplot): each curve titled with its kind's profile and life.
  if (millwear::testing::run_shell("command -v gnuplot >/dev/null").exit_code == 0) {
    EXPECT_GT(fs::file_size(out / "plots/kinds_area.png"), 1000u);
    const std::string svg = slurp(out / "plots/kinds_area.svg");
    char life[64];
    std::snprintf(life, sizeof life, "lab-lo: life %.0f h", l1);
    EXPECT_NE(svg.find(life), std::string::npos) << life;
    EXPECT_NE(svg.find("replacement height"), std::string::npos);
  }
}

// With replicates, every kind's figures in summary.csv are the mean of the histories' (their
// rows in replicates.csv) with the standard error of that mean: for two histories, half their
// difference. With one history they carry batch-means errors.
TEST(Pattern, KindColumnsFoldTheReplicatesWithTheirErrors) {
  TempDir dir("millwear-liner-input-hilo-replicates");
  const fs::path out = run_hilo_lab(dir, " --replicates 2");
  ASSERT_FALSE(::testing::Test::HasFailure());
  const io::CsvData sum = io::read_csv((out / "summary.csv").string());
  const io::CsvData reps = io::read_csv((out / "replicates.csv").string());
  ASSERT_EQ(sum.row_count(), 2u);
  ASSERT_EQ(reps.row_count(), 4u);  // 2 histories x 2 stages
  for (std::size_t row = 0; row < sum.row_count(); ++row) {
    const double stage = sum.number(row, "stage");
    for (const char* kind : {"kind0_", "kind1_"})
      for (const char* c : {"area_mm2", "area_loss_pct", "height_mm", "area_loss_rate_mm2_per_1000h", "life_h"}) {
        const std::string col = std::string(kind) + c;
        std::vector<double> x;
        for (std::size_t i = 0; i < reps.row_count(); ++i)
          if (reps.number(i, "stage") == stage) {
            x.push_back(reps.number(i, col));
            // Each history's own row carries its batch-means error.
            if (stage > 0.0 || std::string(c) == "area_loss_rate_mm2_per_1000h") {
              EXPECT_GT(reps.number(i, col + "_se"), 0.0) << col << " stage " << stage;
            }
          }
        ASSERT_EQ(x.size(), 2u) << col;
        const double scale = std::max(std::fabs(x[0]), 1.0);
        EXPECT_NEAR(sum.number(row, col), 0.5 * (x[0] + x[1]), 1e-8 * scale) << col << " stage " << stage;
        EXPECT_NEAR(sum.number(row, col + "_se"), 0.5 * std::fabs(x[0] - x[1]), 1e-8 * scale) << col << " stage " << stage;
      }
  }
  // The histories differ where the charge does: the wear rates of stage 0.
  EXPECT_GT(sum.number(0, "kind0_area_loss_rate_mm2_per_1000h_se"), 0.0);
  EXPECT_EQ(sum.text(0, sum.column("error_source")), "replicates");
}

// ---- run --continue --------------------------------------------------------------------

// A finished stage written again over itself (the stage a run continues from, worn through
// anew: its record then holds the new wear's errors) and stopped while its files were
// replaced: each file, old or new, matches the marker and the stage reads; a file that is
// neither is refused as before.
TEST(StageFiles, AStageWrittenAgainReadsWhetherEachFileIsOldOrNew) {
  TempDir dir("millwear-stage-rewrite");
  const fs::path run = dir.path() / "run";
  const auto r = millwear::testing::run_millwear("run " + millwear::testing::quoted(source_path("tests/data/lab-quick.toml")) +
                                                 " -o " + millwear::testing::quoted(run) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string out = (dir.path() / "copy").string();
  StageRecord rec = study::read_stage_state(run.string(), "lab-quick", 0);
  study::write_stage_state(out, "lab-quick", rec);
  const std::string marker = io::stage_done_marker(out, "lab-quick", 0);
  const fs::path record = fs::path(out) / "stages/lab-quick_stage0.record";
  const io::KeyValues old_marker = io::read_key_values(marker);
  const std::string old_record = slurp(record);
  StageRecord again = rec;
  again.worn_se.area_m2 = 2.0 * rec.worn_se.area_m2;
  study::write_stage_state(out, "lab-quick", again);
  const std::string new_record = slurp(record);
  ASSERT_NE(old_record, new_record);
  EXPECT_EQ(io::find_value(io::read_key_values(marker), "next.hash.record"), "");  // finished: no pending hashes
  // The state a stop leaves once the marker took the new hashes: the record old, or new.
  io::KeyValues pending;
  for (const auto& kv : old_marker)
    if (kv.first != "design" && kv.first != "stage") pending.push_back(kv);
  for (const auto& [key, hash] : io::read_key_values(marker))
    if (key.rfind("hash.", 0) == 0) pending.emplace_back("next." + key, hash);
  io::write_stage_done(out, "lab-quick", 0, pending);
  for (const std::string& text : {old_record, new_record}) {
    std::ofstream(record, std::ios::binary) << text;
    const StageRecord read = study::read_stage_state(out, "lab-quick", 0);
    EXPECT_EQ(read.worn_se.area_m2, text == old_record ? rec.worn_se.area_m2 : again.worn_se.area_m2);
  }
  std::string other = old_record;
  other.insert(other.find('\n') + 1, "# neither\n");
  std::ofstream(record, std::ios::binary) << other;
  EXPECT_THROW(study::read_stage_state(out, "lab-quick", 0), InputError);
}

TEST(Continue, SameConditionsReproduceTheLaterStagesByteForByte) {
  TempDir dir("millwear-liner-input-cont");
  const std::string lab = source_path("profiles/lab-2x30.toml");
  const std::string scene = dir.write("lab4.toml", lab_scene_text("rows = 12\nprofile = \"" + lab + "\"", "", 4));
  std::string fast_text = lab_scene_text("rows = 12\nprofile = \"" + lab + "\"", "", 4);
  fast_text.replace(fast_text.find("speed = 0.75"), 12, "speed = 0.85");
  const std::string fast = dir.write("lab4fast.toml", fast_text);
  const fs::path first = dir.path() / "first", again = dir.path() / "again", faster = dir.path() / "faster";
  auto quoted = [](const fs::path& p) { return millwear::testing::quoted(p); };
  using millwear::testing::run_millwear;
  auto r = run_millwear("run " + quoted(scene) + " -o " + quoted(first) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(again) + " --continue " + quoted(first) + " --stage 2 -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const std::string f : {"profiles/lab-mill_stage3.csv", "profiles/lab-mill_stage4.csv",
                              "stages/lab-mill_stage3.units.csv", "stages/lab-mill_stage4.units.csv",
                              "stages/lab-mill_stage3.edges.csv", "stages/lab-mill_stage4.charge.csv"}) {
    ASSERT_TRUE(fs::exists(again / f)) << f;
    EXPECT_EQ(slurp(first / f), slurp(again / f)) << f;
  }
  const auto m = nlohmann::json::parse(slurp(again / "manifest.json"));
  EXPECT_EQ(m["designs"][0]["continued_from"]["stage"], 2);
  EXPECT_TRUE(m["designs"][0]["continued_from"]["changes"].empty());

  // A new speed: recorded, and the life counted from stage 2's hours.
  r = run_millwear("run " + quoted(fast) + " -o " + quoted(faster) + " --continue " + quoted(first) + " --stage 2 -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto f = nlohmann::json::parse(slurp(faster / "manifest.json"))["designs"][0];
  bool speed_recorded = false;
  for (const auto& c : f["continued_from"]["changes"])
    speed_recorded = speed_recorded || c.get<std::string>().rfind("mill.speed_fraction_critical: 0.75 -> 0.85", 0) == 0;
  EXPECT_TRUE(speed_recorded) << f["continued_from"].dump();
  EXPECT_DOUBLE_EQ(f["continued_from"]["hours"].get<double>(), 200.0);
  EXPECT_DOUBLE_EQ(f["life_from_hours"].get<double>(), 200.0);
  EXPECT_NEAR(f["remaining_life_h"].get<double>(), f["life_h"].get<double>() - 200.0, 1e-9);
  // Stages 0-2 are the first run's; stage 3 was worn at the new speed.
  EXPECT_EQ(slurp(first / "profiles/lab-mill_stage2.csv"), slurp(faster / "profiles/lab-mill_stage2.csv"));
  EXPECT_NE(slurp(first / "profiles/lab-mill_stage3.csv"), slurp(faster / "profiles/lab-mill_stage3.csv"));
  // The errors of stage 3's area and height are those of the wear done at the new speed (kept
  // in stage 2's record, which the wear from stage 2 on wrote again); at the same speed the
  // record is the first run's to the byte.
  const auto worn_se = [](const fs::path& out, int stage) {
    const auto kv = millwear::study::read_stage_state(out.string(), "lab-mill", stage).worn_se;
    return std::make_pair(kv.area_m2, kv.height_m);
  };
  EXPECT_EQ(slurp(first / "stages/lab-mill_stage2.record"), slurp(again / "stages/lab-mill_stage2.record"));
  EXPECT_NE(worn_se(first, 2).first, worn_se(faster, 2).first);
  EXPECT_NE(worn_se(first, 2).second, worn_se(faster, 2).second);
  EXPECT_EQ(worn_se(first, 1), worn_se(faster, 1));
  const auto area_se_at = [](const fs::path& out, int stage) {
    const millwear::io::CsvData t = millwear::io::read_csv((out / "summary.csv").string());
    const auto stages = t.numbers("stage"), se = t.numbers("area_mm2_se");
    for (std::size_t i = 0; i < stages.size(); ++i)
      if (static_cast<int>(stages[i]) == stage) return se[i];
    return std::nan("");
  };
  EXPECT_EQ(area_se_at(first, 3), area_se_at(again, 3));
  EXPECT_NE(area_se_at(first, 3), area_se_at(faster, 3));

  // A stage the first run did not finish is refused (exit 2, naming --stage).
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(dir.path() / "x") + " --continue " + quoted(first) +
                   " --stage 7 -q");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--stage"), std::string::npos) << r.output;
  // From the run's last stage (the default) the scene's own stages end where the run ended:
  // the refusal says how to go on.
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(dir.path() / "y") + " --continue " + quoted(first) + " -q");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("wear.stages: more stages than the one the run continues from (4)"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("--set wear.stages=8"), std::string::npos) << r.output;
  // A profile of the same name with other points is another lifter: refused, nothing written.
  std::string taller = slurp(lab);
  taller.replace(taller.find("height = 20.0"), 13, "height = 22.0");
  const std::string taller_profile = dir.write("lab-2x30.toml", taller);
  const std::string other = dir.write("lab4other.toml", lab_scene_text("rows = 12\nprofile = \"" + taller_profile + "\"", "", 8));
  r = run_millwear("run " + quoted(other) + " -o " + quoted(dir.path() / "z") + " --continue " + quoted(first) + " -q");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("lifters.profile: the mill of the run it continues"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("a profile of other points, under the same name"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir.path() / "z"));
  // The copied stages' figures per mill and their g/kWh come from the mill's length, the
  // slice's thickness and the liner's density: another of any is refused, nothing written.
  for (const char* set : {"mill.length=1.0", "mill.slice_thickness=0.05", "wear.liner_density=4000"}) {
    const std::string key = std::string(set).substr(0, std::string(set).find('='));
    r = run_millwear("run " + quoted(scene) + " -o " + quoted(dir.path() / "w") + " --continue " + quoted(first) +
                     " --stage 1 --set " + set + " -q");
    EXPECT_EQ(r.exit_code, 2) << set << ": " << r.output;
    EXPECT_NE(r.output.find(key + ": the mill of the run it continues"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir.path() / "w")) << set;
  }
  // Listed sizes: the seed places the disks of a fill only. Continued from stage 1, whose
  // charge is carried on, a new seed changes nothing, and --check says so; from stage 0,
  // which starts from a fill, it is a change like any other.
  std::string listed_text = lab_scene_text("rows = 12\nprofile = \"" + lab + "\"", "", 4);
  const std::string range_line = "size_range = [15.0, 25.0]";
  ASSERT_NE(listed_text.find(range_line), std::string::npos);
  listed_text.replace(listed_text.find(range_line), range_line.size(),
                      "sizes = [15.0, 20.0, 25.0]\nmass_fractions = [0.3, 0.4, 0.3]");
  const std::string listed = dir.write("lab4listed.toml", listed_text);
  const fs::path listed_run = dir.path() / "listed";
  r = run_millwear("run " + quoted(listed) + " -o " + quoted(listed_run) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const int stage : {1, 0}) {
    r = run_millwear("run " + quoted(listed) + " -o " + quoted(dir.path() / "v") + " --continue " +
                     quoted(listed_run) + " --stage " + std::to_string(stage) + " --set solver.seed=2 --check");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("solver.seed: 1 -> 2"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("solver.seed: 1 -> 2 (no effect: the charge is carried on from stage 1") != std::string::npos,
              stage == 1)
        << r.output;
    EXPECT_EQ(r.output.find("charge: other disks"), std::string::npos) << r.output;
  }
}

// The library backend hands the masses back in single precision: its charge is still the
// same disks, carried on, and the continued stage is the uninterrupted run's to the byte.
TEST(Continue, TheLibraryBackendsChargeIsCarriedOn) {
  TempDir dir("millwear-liner-input-box2d");
  const std::string scene = source_path("scenarios/lab-mill.toml");
  const fs::path one = dir.path() / "one", two = dir.path() / "two", on = dir.path() / "on";
  auto quoted = [](const fs::path& p) { return millwear::testing::quoted(p); };
  using millwear::testing::run_millwear;
  const std::string box2d = " --fidelity draft -q --set solver.backend=box2d";
  auto r = run_millwear("run " + quoted(scene) + " -o " + quoted(one) + box2d + " --set wear.stages=1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(two) + box2d + " --set wear.stages=2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(on) + box2d + " --set wear.stages=2 --continue " +
                   quoted(one));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto m = nlohmann::json::parse(slurp(on / "manifest.json"));
  for (const auto& c : m["designs"][0]["continued_from"]["changes"])
    EXPECT_NE(c.get<std::string>().rfind("charge:", 0), 0u) << c;
  for (const std::string f : {"profiles/lab-mill_stage2.csv", "stages/lab-mill_stage2.charge.csv"})
    EXPECT_EQ(slurp(two / f), slurp(on / f)) << f;
}

// A lifter at or under the replacement height at the stage a run continues from was due for
// relining before it: its life is behind it, and the remaining life would be negative. The
// continued run is refused before anything is written (exit 2, naming the scene file,
// wear.replacement_height, the stage, its height and the limit); a limit under the lifter runs.
TEST(Continue, ALifterAlreadyPastTheReplacementHeightIsRefused) {
  TempDir dir("millwear-liner-input-cont-past");
  const std::string lab = source_path("profiles/lab-2x30.toml");
  const std::string scene = dir.write("lab.toml", lab_scene_text("rows = 12\nprofile = \"" + lab + "\"", "", 1));
  const fs::path first = dir.path() / "first", next = dir.path() / "next";
  auto quoted = [](const fs::path& p) { return millwear::testing::quoted(p); };
  using millwear::testing::run_millwear;
  auto r = run_millwear("run " + quoted(scene) + " -o " + quoted(first) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const double h_mm = in_mm(study::read_stage_state(first.string(), "lab-mill", 1).lifter.height_m);
  ASSERT_LT(h_mm, 19.9);  // worn below the new 20 mm, so a limit between them is valid
  char set[96];
  std::snprintf(set, sizeof set, " --set wear.stages=2 --set wear.replacement_height=%.6f", h_mm + 0.05);
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(next) + " --continue " + quoted(first) + set + " -q");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(scene + ": wear.replacement_height: a lifter above the replacement height"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("at stage 1 of " + first.string() + " (100 h) the lifter is"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("has no life left to run"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(next));
  // From stage 0 (the new lifter) the same limit is ahead of it.
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(next) + " --continue " + quoted(first) + " --stage 0" + set +
                   " --check");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::snprintf(set, sizeof set, " --set wear.stages=2 --set wear.replacement_height=%.6f", h_mm - 0.05);
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(next) + " --continue " + quoted(first) + set + " --check");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// A continued run's clock is the run's: its stage K at the hours the run recorded. A scene
// whose own start differs from the run's is refused (exit 2, naming lifters.start_hours and
// both starts) rather than run with that start overwritten; the run's own start goes on.
TEST(Continue, AStartOtherThanTheRunsIsRefused) {
  TempDir dir("millwear-liner-input-cont-start");
  const std::string lab = source_path("profiles/lab-2x30.toml");
  const std::string scene = dir.write("lab.toml", lab_scene_text("rows = 12\nprofile = \"" + lab + "\"", "", 1));
  const fs::path first = dir.path() / "first", next = dir.path() / "next";
  auto quoted = [](const fs::path& p) { return millwear::testing::quoted(p); };
  using millwear::testing::run_millwear;
  auto r = run_millwear("run " + quoted(scene) + " -o " + quoted(first) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string go_on = "run " + quoted(scene) + " -o " + quoted(next) + " --continue " + quoted(first) +
                            " --set wear.stages=2 --check";
  r = run_millwear(go_on + " --set lifters.start_hours=500");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(scene + ": lifters.start_hours: the start of the run it continues or none (" + first.string() +
                          " -> the scene: 0.0 -> 500.0 h)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("from stage 1 at 100 h"), std::string::npos) << r.output;
  r = run_millwear(go_on + " --set lifters.start_hours=0");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(next));
}

// A continued run writes beside the run it continues, not into it: OUT the run's folder, a
// folder inside it (however written) or a new one inside it are refused before any work
// (exit 2, naming -o), and nothing is made in the run.
TEST(Continue, AnOutputFolderInsideTheRunIsRefused) {
  TempDir dir("millwear-liner-input-cont-inside");
  const std::string lab = source_path("profiles/lab-2x30.toml");
  const std::string scene = dir.write("lab.toml", lab_scene_text("rows = 12\nprofile = \"" + lab + "\"", "", 1));
  const fs::path first = dir.path() / "first";
  auto quoted = [](const fs::path& p) { return millwear::testing::quoted(p); };
  using millwear::testing::run_millwear;
  auto r = run_millwear("run " + quoted(scene) + " -o " + quoted(first) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const fs::path& out : {first, first / "next", first / "stages" / ".." / "next" / "deeper", first / "plots"}) {
    r = run_millwear("run " + quoted(scene) + " -o " + quoted(out) + " --continue " + quoted(first) +
                     " --set wear.stages=2 -q");
    EXPECT_EQ(r.exit_code, 2) << out << "\n" << r.output;
    EXPECT_NE(r.output.find("-o: an output folder other than the run it continues"), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(first / "next"));
  // Beside it, with a name that starts like the run's: the run goes on.
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(dir.path() / "first-next") + " --continue " +
                   quoted(first) + " --set wear.stages=2 --check");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  // More replicates than the run had: the replicate it lacks is named as one, where the message
  // asked for a design called 'NAME.r2' as if it were the scene's name.
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(dir.path() / "first-next") + " --continue " +
                   quoted(first) + " --set wear.stages=2 --replicates 2 --check");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("a run with replicate 2 of design"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("(the scene's name)"), std::string::npos) << r.output;
}

// A continuation lists what it changes and nothing it did not: other stage hours move the
// start the run's clock sets, which is not listed (it read `wear.start_hours: 0.0 -> -50.0`);
// and from a run of two histories per design, one continued says its rows are the first
// history's, not the run's mean (it said nothing), where --replicates 2 continues both.
TEST(Continue, TheChangesListedAreTheScenesAndAHistoryLeftBehindIsNamed) {
  TempDir dir("millwear-liner-input-cont-listed");
  const std::string lab = source_path("profiles/lab-2x30.toml");
  const std::string scene = dir.write("lab.toml", lab_scene_text("rows = 12\nprofile = \"" + lab + "\"", "", 1));
  const fs::path first = dir.path() / "first";
  auto quoted = [](const fs::path& p) { return millwear::testing::quoted(p); };
  using millwear::testing::run_millwear;
  auto r = run_millwear("run " + quoted(scene) + " -o " + quoted(first) + " -q --replicates 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string next = " -o " + quoted(dir.path() / "next") + " --continue " + quoted(first) + " --stage 1";
  r = run_millwear("run " + quoted(scene) + next + " --set wear.stages=3 --set wear.stage_hours=250 --check");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("wear.stage_hours:"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("wear.start_hours"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("replicates: 2 histories of"), std::string::npos) << r.output;
  r = run_millwear("run " + quoted(scene) + next + " --set wear.stages=3 --replicates 2 --check");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("replicates:"), std::string::npos) << r.output;
  // A continuation from another stage into that folder is refused naming the two stages, where
  // it blamed other scene or profile files.
  r = run_millwear("run " + quoted(scene) + next + " --set wear.stages=2 -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(dir.path() / "next") + " --continue " + quoted(first) +
                   " --stage 0 --set wear.stages=2 -q");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--continue: " + first.string() + " stage 1 then, " + first.string() + " stage 0 now"),
            std::string::npos)
      << r.output;
}

// A pattern's kinds are the scene's lifters.pattern: a continued run whose pattern lists the
// run's kinds in the other order (which also changes the first kind, the manifest's
// lifter_profile) is refused naming lifters.pattern, the key the scene has; and a kind under
// the replacement height at that stage is named by its index and profile.
TEST(Continue, APatternOfOtherKindsIsNamedAsThePatternAndEachKindIsChecked) {
  TempDir dir("millwear-liner-input-cont-pattern");
  const std::string hi = source_path("profiles/lab-2x30.toml"), lo = source_path("profiles/lab-lo.toml");
  const std::string scene = dir.write("hilo.toml", lab_scene_text("rows = 12\npattern = [\"" + hi + "\", \"" + lo + "\"]", "", 1));
  const std::string swapped =
      dir.write("lohi.toml", lab_scene_text("rows = 12\npattern = [\"" + lo + "\", \"" + hi + "\"]", "", 2));
  const fs::path first = dir.path() / "first", next = dir.path() / "next";
  auto quoted = [](const fs::path& p) { return millwear::testing::quoted(p); };
  using millwear::testing::run_millwear;
  auto r = run_millwear("run " + quoted(scene) + " -o " + quoted(first) + " -q");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_millwear("run " + quoted(swapped) + " -o " + quoted(next) + " --continue " + quoted(first) + " -q");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(swapped + ": lifters.pattern: the mill of the run it continues"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("lifters.profile"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(next));
  // The low kind (12 mm new) under a limit just above its stage-1 height; the high kind is far
  // above it.
  const StageRecord from = study::read_stage_state(first.string(), "lab-mill", 1);
  ASSERT_EQ(from.kinds.size(), 2u);
  const double lo_mm = in_mm(from.kinds[1].height_m);
  ASSERT_LT(lo_mm, 11.9);
  char set[96];
  std::snprintf(set, sizeof set, " --set wear.stages=2 --set wear.replacement_height=%.6f", lo_mm + 0.05);
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(next) + " --continue " + quoted(first) + set + " -q");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("kind 1 ('lab-lo') is"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(next));
}

// A new filling is a charge of other disks: stage N goes on with the new filling's charge,
// filled anew on its liner (not the run's disks under the new filling's name), the manifest
// says so, and a resume of the continued run fills the same charge to the same bits.
TEST(Continue, ANewFillingFillsTheChargeAnewAndResumesToTheSameBits) {
  TempDir dir("millwear-liner-input-refill");
  const std::string scene = source_path("scenarios/lab-mill.toml");
  const fs::path first = dir.path() / "first", whole = dir.path() / "whole", part = dir.path() / "part";
  auto quoted = [](const fs::path& p) { return millwear::testing::quoted(p); };
  using millwear::testing::run_millwear;
  const std::string draft = " --fidelity draft -q";
  auto r = run_millwear("run " + quoted(scene) + " -o " + quoted(first) + draft + " --set wear.stages=1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string go_on = " --continue " + quoted(first) + " --stage 1 --set wear.stages=3 --set charge.filling=0.2" +
                            " --set charge.ball_filling=0.2" + draft;
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(whole) + go_on);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto lines = [](const fs::path& f) {
    const std::string text = slurp(f);
    return std::count(text.begin(), text.end(), '\n');
  };
  // Two thirds of the balls: the charge stage 2 ran on is the new filling's, not the run's.
  const auto before = lines(first / "stages/lab-mill_stage1.charge.csv");
  const auto after = lines(whole / "stages/lab-mill_stage2.charge.csv");
  EXPECT_LT(after, before * 3 / 4) << before << " disks before, " << after << " after";
  EXPECT_GT(after, before / 2) << before << " disks before, " << after << " after";
  EXPECT_FALSE(fs::exists(whole / "stages/lab-mill_stage1.start.csv"));
  bool said = false;
  const auto m = nlohmann::json::parse(slurp(whole / "manifest.json"));
  for (const auto& c : m["designs"][0]["continued_from"]["changes"])
    said = said || c.get<std::string>().rfind("charge: other disks", 0) == 0;
  EXPECT_TRUE(said) << m["designs"][0]["continued_from"].dump();

  // --check says so before anything runs.
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(dir.path() / "checked") + go_on + " --check");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("charge: other disks than stage 1"), std::string::npos) << r.output;
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(part) + go_on + " --stop-after-stage 2");
  EXPECT_NE(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(part / "stages/lab-mill_stage2.done"));
  ASSERT_FALSE(fs::exists(part / "stages/lab-mill_stage3.done"));
  // The same stop with the copies of stages 1 and 2 lost (a kill while they were written):
  // the resume takes them from the run it continues.
  const fs::path lost = dir.path() / "lost";
  fs::copy(part, lost, fs::copy_options::recursive);
  for (const auto& e : fs::directory_iterator(lost / "stages")) {
    const std::string name = e.path().filename().string();
    if (name.rfind("lab-mill_stage1.", 0) == 0 || name.rfind("lab-mill_stage2.", 0) == 0) fs::remove(e.path());
  }
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(part) + go_on + " --resume");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = run_millwear("run " + quoted(scene) + " -o " + quoted(lost) + go_on + " --resume");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const std::string f : {"profiles/lab-mill_stage3.csv", "stages/lab-mill_stage3.charge.csv",
                              "stages/lab-mill_stage3.units.csv", "summary.csv"}) {
    EXPECT_EQ(slurp(whole / f), slurp(part / f)) << f;
    EXPECT_EQ(slurp(whole / f), slurp(lost / f)) << f;
  }
}

}  // namespace
}  // namespace millwear
