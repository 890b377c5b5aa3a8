// Lifter profiles: analytic trapezoid metrics, match_area_of, and rejection of bad files.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "common/errors.hpp"
#include "common/units.hpp"
#include "profiles/profile.hpp"
#include "temp_dir.hpp"

using namespace millwear;
namespace fs = std::filesystem;
using millwear::testing::TempDir;

namespace {

constexpr double kDeg = kPi / 180.0;

std::string shipped(const std::string& name) {
  return std::string(MILLWEAR_SOURCE_DIR) + "/profiles/" + name;
}

// A fresh folder per test for bad profile files.
class ProfileFile : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  // Load and return the error; fails the test if no InputError is thrown.
  InputError load_error(const std::string& path) {
    try {
      load_profile(path);
    } catch (const InputError& e) {
      return e;
    }
    ADD_FAILURE() << "no InputError for " << path;
    return InputError("", "", "");
  }
  TempDir dir_{"millwear-profiles"};
};

const char* kGood =
    "form = \"trapezoid\"\nheight = 200.0\ntop_width = 100.0\n"
    "leading_face_angle = 30.0\ntrailing_face_angle = 30.0\n";

}  // namespace

TEST(Profile, TrapezoidAreaAndHeightMatchAnalyticValues) {
  TrapezoidDef t{0.2, 0.1, 30 * kDeg, 5 * kDeg};
  const Polyline pts = trapezoid_points(t);
  const ProfileMetrics m = measure_profile(pts);
  const double base = 0.1 + 0.2 * (std::tan(30 * kDeg) + std::tan(5 * kDeg));
  // Tolerances: a few ulps of the metre-scale inputs (1e-12 relative).
  EXPECT_NEAR(m.area_m2, 0.5 * 0.2 * (0.1 + base), 1e-12);
  EXPECT_NEAR(m.height_m, 0.2, 1e-15);
  EXPECT_NEAR(m.base_width_m, base, 1e-15);
  EXPECT_NEAR(m.top_width_m, 0.1, 1e-15);
  EXPECT_NEAR(m.leading_face_angle_rad, 30 * kDeg, 1e-12);
  EXPECT_NEAR(m.trailing_face_angle_rad, 5 * kDeg, 1e-12);
}

TEST(Profile, TrapezoidBaseIsCentredWithLeadingFaceAtPlusX) {
  const Polyline pts = trapezoid_points({0.2, 0.1, 30 * kDeg, 0.0});
  ASSERT_EQ(pts.size(), 4u);
  EXPECT_NEAR(pts.front().x + pts.back().x, 0.0, 1e-15);
  EXPECT_NEAR(pts[1].x, pts[0].x, 1e-15);  // trailing face vertical (0 deg) at -x
  EXPECT_NEAR(pts[3].x - pts[2].x, 0.2 * std::tan(30 * kDeg), 1e-15);
}

TEST(Profile, TopWidthForAreaReproducesTheArea) {
  TrapezoidDef t{0.2, 0.0, 30 * kDeg, 5 * kDeg};
  t.top_width_m = top_width_for_area(t, 0.043, "x.toml");
  EXPECT_NEAR(measure_profile(trapezoid_points(t)).area_m2, 0.043, 1e-12);
  EXPECT_THROW(top_width_for_area(t, 0.001, "x.toml"), InputError);  // faces alone exceed it
}

TEST(Profile, MatchAreaOfGivesEqualAreas) {
  const LifterProfile a = load_profile(shipped("2x30.toml"));
  const LifterProfile b = load_profile(shipped("1x30.toml"));
  const LifterProfile c = load_profile(shipped("rect.toml"));
  const double area_a = measure_profile(a.points).area_m2;
  // 1e-6 relative is the stated accuracy; the closed form is exact to rounding.
  EXPECT_NEAR(measure_profile(b.points).area_m2 / area_a, 1.0, 1e-6);
  EXPECT_NEAR(measure_profile(c.points).area_m2 / area_a, 1.0, 1e-6);
  EXPECT_NEAR(b.trapezoid.trailing_face_angle_rad, 5 * kDeg, 1e-12);
}

TEST(Profile, ShippedFilesConvertMillimetresToMetres) {
  const LifterProfile p = load_profile(shipped("2x30.toml"));
  EXPECT_EQ(p.name, "2x30");
  EXPECT_EQ(p.form, ProfileForm::Trapezoid);
  const ProfileMetrics m = measure_profile(p.points);
  EXPECT_NEAR(m.height_m, 0.200, 1e-12);
  EXPECT_NEAR(m.top_width_m, 0.100, 1e-12);
  EXPECT_NEAR(m.base_width_m, 0.1 + 0.4 * std::tan(30 * kDeg), 1e-12);

  const LifterProfile q = load_profile(shipped("hi-lo-example.toml"));
  EXPECT_EQ(q.form, ProfileForm::Polyline);
  EXPECT_GE(q.points.size(), 6u);
  EXPECT_NEAR(measure_profile(q.points).height_m, 0.200, 1e-12);
}

TEST_F(ProfileFile, NameDefaultsToFileStem) {
  EXPECT_EQ(load_profile(write("my-lifter.toml", kGood)).name, "my-lifter");
}

TEST_F(ProfileFile, MissingKeyIsNamed) {
  const std::string f = write("p.toml",
                              "form = \"trapezoid\"\ntop_width = 100.0\n"
                              "leading_face_angle = 30.0\ntrailing_face_angle = 30.0\n");
  const InputError e = load_error(f);
  EXPECT_EQ(e.file, f);
  EXPECT_EQ(e.where, "height");
  EXPECT_NE(e.expected.find("missing"), std::string::npos);
}

// A trapezoid written in metres (a 20 mm lifter as height = 0.02) spans under a millimetre:
// refused naming the height, as a polyline or a scan in metres is.
TEST_F(ProfileFile, ATrapezoidInMetresIsRefusedNamingTheHeight) {
  const InputError e = load_error(write("p.toml",
                                        "form = \"trapezoid\"\nheight = 0.02\ntop_width = 0.01\n"
                                        "leading_face_angle = 30.0\ntrailing_face_angle = 30.0\n"));
  EXPECT_EQ(e.where, "height");
  EXPECT_NE(e.expected.find("are they in metres?"), std::string::npos) << e.what();
  EXPECT_NO_THROW(load_profile(write("q.toml", "form = \"trapezoid\"\nheight = 2.0\ntop_width = 1.0\n"
                                               "leading_face_angle = 30.0\ntrailing_face_angle = 30.0\n")));
}

TEST_F(ProfileFile, NegativeHeightIsRejected) {
  const InputError e = load_error(write("p.toml",
                                        "form = \"trapezoid\"\nheight = -200.0\ntop_width = 100\n"
                                        "leading_face_angle = 30.0\ntrailing_face_angle = 30.0\n"));
  EXPECT_EQ(e.where, "height");
  EXPECT_NE(e.expected.find("in (0, 5000]"), std::string::npos);
}

TEST_F(ProfileFile, FaceAngleOf90DegreesIsRejected) {
  const InputError e = load_error(write("p.toml",
                                        "form = \"trapezoid\"\nheight = 200.0\ntop_width = 100\n"
                                        "leading_face_angle = 90.0\ntrailing_face_angle = 30.0\n"));
  EXPECT_EQ(e.where, "leading_face_angle");
  EXPECT_NE(e.expected.find("< 90"), std::string::npos);
}

TEST_F(ProfileFile, NegativeFaceAngleIsRejected) {
  const InputError e = load_error(write("p.toml",
                                        "form = \"trapezoid\"\nheight = 200.0\ntop_width = 100\n"
                                        "leading_face_angle = 30.0\ntrailing_face_angle = -1\n"));
  EXPECT_EQ(e.where, "trailing_face_angle");
}

TEST_F(ProfileFile, SelfIntersectingPolylineIsRejected) {
  const InputError e = load_error(write(
      "p.toml", "form = \"polyline\"\n"
                "points = [[-100, 0], [50, 200], [-50, 200], [100, 0]]\n"));  // top crosses
  EXPECT_EQ(e.where, "points");
  EXPECT_NE(e.expected.find("cross"), std::string::npos);
}

TEST_F(ProfileFile, FootOffTheShellIsRejected) {
  const InputError e = load_error(write(
      "p.toml", "form = \"polyline\"\npoints = [[-100, 0], [-50, 200], [50, 200], [100, 5]]\n"));
  EXPECT_EQ(e.where, "points");
  EXPECT_NE(e.expected.find("y = 0"), std::string::npos);
}

TEST_F(ProfileFile, UnknownKeyIsNamed) {
  const InputError e = load_error(write("p.toml", std::string(kGood) + "heigth = 3\n"));
  EXPECT_EQ(e.where, "heigth");
  EXPECT_NE(e.expected.find("unknown key"), std::string::npos);
  EXPECT_NE(e.expected.find("line 6"), std::string::npos);
}

TEST_F(ProfileFile, WrongTypeIsRejected) {
  const InputError e = load_error(write("p.toml",
                                        "form = \"trapezoid\"\nheight = \"tall\"\ntop_width = 1\n"
                                        "leading_face_angle = 30.0\ntrailing_face_angle = 30.0\n"));
  EXPECT_EQ(e.where, "height");
  EXPECT_NE(e.expected.find("line 2"), std::string::npos);
}

TEST_F(ProfileFile, NotTomlGivesTheLine) {
  const InputError e = load_error(write("p.toml", "form = \"trapezoid\"\n\x7f\x45LF garbage ]]]\n"));
  EXPECT_EQ(e.where, "line 2");
  EXPECT_NE(e.expected.find("TOML"), std::string::npos);
}

TEST_F(ProfileFile, MissingFileIsRejected) {
  const InputError e = load_error((dir_ / "nope.toml").string());
  EXPECT_NE(e.expected.find("existing"), std::string::npos);
}

TEST_F(ProfileFile, MatchAreaOfMissingFileIsRejected) {
  const InputError e = load_error(write("p.toml",
                                        "form = \"trapezoid\"\nheight = 200.0\n"
                                        "leading_face_angle = 30.0\ntrailing_face_angle = 5\n"
                                        "match_area_of = \"absent.toml\"\n"));
  EXPECT_EQ(e.where, "match_area_of");
  EXPECT_NE(e.expected.find("absent.toml"), std::string::npos);
}

// A trapezoid can take the area of a measured lifter: a scan of a worn one, say.
TEST_F(ProfileFile, MatchAreaOfAMeasuredLifterTakesItsArea) {
  const std::string scan = shipped("lab-survey-2000h.csv");
  const double target = measure_profile(load_profile(scan).points).area_m2;
  const LifterProfile p = load_profile(write("p.toml",
                                             "form = \"trapezoid\"\nheight = 15.0\nleading_face_angle = 30.0\n"
                                             "trailing_face_angle = 30.0\nmatch_area_of = \"" + scan + "\"\n"));
  EXPECT_NEAR(measure_profile(p.points).area_m2 / target, 1.0, 1e-6);
}

TEST_F(ProfileFile, CircularMatchAreaOfIsRejected) {
  const char* a =
      "form = \"trapezoid\"\nheight = 200.0\nleading_face_angle = 30.0\n"
      "trailing_face_angle = 5\nmatch_area_of = \"b.toml\"\n";
  const char* b =
      "form = \"trapezoid\"\nheight = 200.0\nleading_face_angle = 30.0\n"
      "trailing_face_angle = 5\nmatch_area_of = \"a.toml\"\n";
  write("b.toml", b);
  const InputError e = load_error(write("a.toml", a));
  EXPECT_EQ(e.where, "match_area_of");
  // The loop is named file by file (two files were "a file that refers back to itself").
  EXPECT_NE(e.expected.find("comes back to this file (a.toml -> b.toml -> a.toml)"), std::string::npos) << e.what();
}

// A problem in the file match_area_of names is said with the file that named it.
TEST_F(ProfileFile, AProblemInTheMatchedFileNamesTheFileThatReadIt) {
  write("thin.toml", "form = \"polyline\"\npoints = [[0, 0], [1, 1]]\n");
  const std::string p = write("p.toml", "form = \"trapezoid\"\nheight = 20.0\nleading_face_angle = 30.0\n"
                                        "trailing_face_angle = 30\nmatch_area_of = \"thin.toml\"\n");
  const InputError e = load_error(p);
  EXPECT_EQ(e.where, "points");
  EXPECT_NE(e.expected.find("(the profile match_area_of names in " + p + ")"), std::string::npos) << e.what();
}

TEST_F(ProfileFile, KeyOfTheOtherFormIsRejected) {
  const InputError e =
      load_error(write("p.toml", std::string(kGood) + "points = [[0, 0], [1, 1], [2, 0]]\n"));
  EXPECT_EQ(e.where, "points");
}
