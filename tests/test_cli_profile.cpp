// `millwear profile`: the table, --csv, and exit code 2 with a clear message for bad files.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <string>

#include "cli_support.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using millwear::testing::TempDir;

namespace {

using Result = millwear::testing::CliResult;
constexpr auto run = &millwear::testing::run_millwear;

std::string shipped(const std::string& name) {
  return "\"" + std::string(MILLWEAR_SOURCE_DIR) + "/profiles/" + name + "\"";
}

class CliProfile : public ::testing::Test {
 protected:
  std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  // A bad file must give exit 2 and a message naming the file and the key (or line).
  void expect_rejected(const std::string& text, const std::string& where) {
    const std::string f = write("bad.toml", text);
    const Result r = run("profile \"" + f + "\"");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(f), std::string::npos) << r.output;
    EXPECT_NE(r.output.find(where), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("expected"), std::string::npos) << r.output;
  }
  TempDir dir_{"millwear-cli-profile"};
};

const std::string kAngles = "leading_face_angle = 30.0\ntrailing_face_angle = 30.0\n";

}  // namespace

TEST(Cli, ProfileTableShowsEqualAreasFor2x30And1x30) {
  const Result r = run("profile " + shipped("2x30.toml") + " " + shipped("1x30.toml"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::smatch m2, m1;
  const std::regex r2(R"(\n2x30\s+([0-9.]+)\s+([0-9.]+))"), r1(R"(\n1x30\s+([0-9.]+))");
  ASSERT_TRUE(std::regex_search(r.output, m2, r2)) << r.output;
  ASSERT_TRUE(std::regex_search(r.output, m1, r1)) << r.output;
  EXPECT_EQ(m2[1].str(), m1[1].str());  // printed to 0.1 mm^2
  EXPECT_EQ(m2[2].str(), "200.0");      // height in mm
}

TEST_F(CliProfile, CsvWritesOnePolylinePerProfileInMillimetres) {
  const Result r = run("profile " + shipped("2x30.toml") + " " + shipped("hi-lo-example.toml") +
                       " --csv \"" + (dir_ / "out").string() + "\"");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(dir_ / "out" / "2x30.csv");
  std::string comment, header, first;
  std::getline(in, comment);
  std::getline(in, header);
  std::getline(in, first);
  EXPECT_EQ(comment.rfind("# written by millwear profile: 2x30 from ", 0), 0u) << comment;
  EXPECT_EQ(header, "x_mm,y_mm");
  EXPECT_EQ(first.substr(0, 9), "-165.4700");  // -(100 + 2 * 200 tan 30) / 2 mm
  EXPECT_TRUE(fs::exists(dir_ / "out" / "hi-lo-example.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "out" / "2x30.csv.tmp"));
}

TEST_F(CliProfile, MissingKeyExitsTwo) {
  expect_rejected("form = \"trapezoid\"\ntop_width = 100.0\n" + kAngles, "height");
}

TEST_F(CliProfile, NegativeHeightExitsTwo) {
  expect_rejected("form = \"trapezoid\"\nheight = -1.0\ntop_width = 100.0\n" + kAngles, "height");
}

TEST_F(CliProfile, FaceAngleOf90DegreesExitsTwo) {
  expect_rejected("form = \"trapezoid\"\nheight = 200.0\ntop_width = 100.0\n"
                  "leading_face_angle = 90.0\ntrailing_face_angle = 30.0\n",
                  "leading_face_angle");
}

// Just under 90 degrees the faces lean a base kilometres wide: held to a polyline's bounds.
TEST_F(CliProfile, FacesLeaningTheBaseOutOfBoundsExitTwo) {
  expect_rejected("form = \"trapezoid\"\nheight = 20.0\ntop_width = 10.0\n"
                  "leading_face_angle = 30.0\ntrailing_face_angle = 89.9999\n",
                  "trailing_face_angle");
  const Result ok = run("profile \"" + write("fine.toml", "form = \"trapezoid\"\nheight = 20.0\ntop_width = 10.0\n"
                                                        "leading_face_angle = 30.0\ntrailing_face_angle = 89.9\n") + "\"");
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
}

TEST_F(CliProfile, SelfIntersectingPolylineExitsTwo) {
  expect_rejected("form = \"polyline\"\npoints = [[-100, 0], [50, 200], [-50, 200], [100, 0]]\n",
                  "points");
}

TEST_F(CliProfile, UnknownKeyExitsTwo) {
  expect_rejected("form = \"trapezoid\"\nheight = 200.0\ntop_width = 100.0\n" + kAngles +
                      "colour = \"red\"\n",
                  "colour");
}

TEST_F(CliProfile, NotTomlExitsTwoWithLine) {
  expect_rejected("this is not TOML at all\n", "line 1");
}

// A scene or a comparison where a profile belongs: the message says what the file is.
TEST_F(CliProfile, ASceneFileGivenAsAProfileIsNamedAsOne) {
  const Result r = run("profile \"" + std::string(MILLWEAR_SOURCE_DIR) + "/scenarios/lab-mill.toml\"");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("lab-mill.toml: form: a lifter profile"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("it is a scene file"), std::string::npos) << r.output;
}

TEST_F(CliProfile, MissingFileExitsTwo) {
  const Result r = run("profile \"" + (dir_ / "absent.toml").string() + "\"");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("absent.toml"), std::string::npos) << r.output;
}

TEST_F(CliProfile, NothingIsWrittenWhenAnyFileIsBad) {
  const std::string bad = write("bad.toml", "form = \"trapezoid\"\n");
  const fs::path out = dir_ / "out";
  const Result r =
      run("profile " + shipped("2x30.toml") + " \"" + bad + "\" --csv \"" + out.string() + "\"");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_FALSE(fs::exists(out / "2x30.csv"));
  EXPECT_EQ(r.output.find("2x30 "), std::string::npos) << "table printed before validation";
}

// --csv replaces an earlier --csv's file, never a file of the user's under the same name.
TEST_F(CliProfile, CsvReplacesItsOwnFileButNotAUsers) {
  const std::string out = (dir_ / "out").string();
  ASSERT_EQ(run("profile " + shipped("2x30.toml") + " --csv \"" + out + "\"").exit_code, 0);
  const Result again = run("profile " + shipped("2x30.toml") + " --csv \"" + out + "\"");
  EXPECT_EQ(again.exit_code, 0) << again.output;
  // A file of the same points without the comment line (as --csv wrote before it had one).
  const std::string text = millwear::testing::read_text(dir_ / "out/2x30.csv");
  write("out/2x30.csv", text.substr(text.find('\n') + 1));
  const Result older = run("profile " + shipped("2x30.toml") + " --csv \"" + out + "\"");
  EXPECT_EQ(older.exit_code, 0) << older.output;
  EXPECT_EQ(millwear::testing::read_text(dir_ / "out/2x30.csv"), text);
  write("out/lab-2x30.csv", "x_mm,y_mm\n-20,0\n0,20\n20,0\n");  // a scan of the user's
  const Result r = run("profile " + shipped("lab-2x30.toml") + " --csv \"" + out + "\"");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("lab-2x30.csv is another (or an older millwear's, of other points)"), std::string::npos)
      << r.output;
  EXPECT_EQ(millwear::testing::read_text(dir_ / "out/lab-2x30.csv"), "x_mm,y_mm\n-20,0\n0,20\n20,0\n");
}

// A measured scan is named after its file: --csv into the scan's own folder would write the
// lifter over the scan. Refused, the scan untouched, nothing printed; so are two profiles of
// one name, before the table.
TEST_F(CliProfile, CsvNeverOverwritesAnInputFile) {
  const std::string scan_text = "# a plant's scan\nx_mm,y_mm\n-20,-1\n-10,0\n-5,20\n5,20\n10,0\n20,-1\n";
  const std::string scan = write("scan.csv", scan_text);
  const Result r = run("profile \"" + scan + "\" --csv \"" + dir_.path().string() + "\"");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("would overwrite it"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("area_mm2"), std::string::npos) << "table printed before the refusal";
  std::ifstream in(scan);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(in), {}), scan_text);

  const std::string a = write("a.toml", "name = \"same\"\nform = \"trapezoid\"\nheight = 20.0\ntop_width = 10.0\n" + kAngles);
  const std::string b = write("b.toml", "name = \"same\"\nform = \"trapezoid\"\nheight = 30.0\ntop_width = 10.0\n" + kAngles);
  const Result twice = run("profile \"" + a + "\" \"" + b + "\" --csv \"" + (dir_ / "out").string() + "\"");
  EXPECT_EQ(twice.exit_code, 2) << twice.output;
  EXPECT_NE(twice.output.find("both would be written"), std::string::npos) << twice.output;
  EXPECT_EQ(twice.output.find("area_mm2"), std::string::npos) << "table printed before the refusal";

  // Nor a file a profile's match_area_of reads, an earlier --csv's though it is: a profile
  // named as that file would write its own points over the area it matches.
  const std::string earlier = (dir_ / "out" / "base.csv").string();
  ASSERT_EQ(run("profile \"" + write("base.toml", "name = \"base\"\nform = \"trapezoid\"\nheight = 20.0\ntop_width = 10.0\n" + kAngles) +
                "\" --csv \"" + (dir_ / "out").string() + "\"").exit_code, 0);
  const std::string written = millwear::testing::read_text(earlier);
  const std::string matched = write("out/matched.toml", "name = \"base\"\nform = \"trapezoid\"\nheight = 15.0\n"
                                                        "match_area_of = \"base.csv\"\n" + kAngles);
  const Result reads = run("profile \"" + matched + "\" --csv \"" + (dir_ / "out").string() + "\"");
  EXPECT_EQ(reads.exit_code, 2) << reads.output;
  EXPECT_NE(reads.output.find("which " + matched + " reads"), std::string::npos) << reads.output;
  EXPECT_EQ(millwear::testing::read_text(earlier), written);
}
