// `millwear view` under a virtual X server (ctest runs this binary through xvfb-run with
// Mesa's software OpenGL): the screenshot shows the charge where it is, scripted controls
// change the charge's regime and its filling, the saved scene reproduces the power the view
// read, and the wear mode draws the profiles `millwear run` writes. Every case runs the lab
// mill at draft fidelity.
#include <gtest/gtest.h>
#include <stb_image.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "temp_dir.hpp"

namespace fs = std::filesystem;
using millwear::testing::TempDir;

namespace {

std::string q(const std::string& s) { return "'" + s + "'"; }
std::string src(const std::string& rel) { return std::string(MILLWEAR_SOURCE_DIR) + "/" + rel; }

struct Result {
  int exit_code = -1;
  std::string out, err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

Result run_millwear(const std::string& args, const fs::path& dir) {
  const fs::path out = dir / "stdout.txt", err = dir / "stderr.txt";
  const std::string cmd = q(MILLWEAR_BINARY) + " " + args + " >" + q(out.string()) + " 2>" + q(err.string());
  const int status = std::system(cmd.c_str());
  Result r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

// The `report` lines of a script run: key=value fields.
std::vector<std::map<std::string, std::string>> reports(const std::string& out) {
  std::vector<std::map<std::string, std::string>> r;
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("t=", 0) != 0) continue;
    std::map<std::string, std::string> f;
    std::istringstream words(line);
    for (std::string w; words >> w;) {
      const auto eq = w.find('=');
      if (eq != std::string::npos) f[w.substr(0, eq)] = w.substr(eq + 1);
      else f["shape"] += (f["shape"].empty() ? "" : " ") + w;  // "toe -30 shoulder 135"
    }
    r.push_back(f);
  }
  return r;
}

double num(const std::map<std::string, std::string>& f, const std::string& k) {
  const auto it = f.find(k);
  return it == f.end() ? NAN : std::strtod(it->second.c_str(), nullptr);
}

void write(const fs::path& p, const std::string& text) {
  std::ofstream o(p);
  o << text;
}

const std::string kLab = src("scenarios/lab-mill.toml");

}  // namespace

// The window's layout (src/view/window.cpp): the mill in the left square of side
// min(width, height), centred, the shell at 0.45 of the side; species 0 is drawn (66,135,245).
// The other tests use a 640 x 400 window: software OpenGL's cost grows with the pixels.
TEST(View, ScreenshotShowsTheChargeInsideTheShell) {
  const TempDir dir("millwear-view-test-shot");
  const std::string png = (dir / "s.png").string();
  // The command as a user types it (the default 1280 x 800 window; the lab scene is draft).
  const Result r = run_millwear("view " + q(kLab) + " --frames 300 --screenshot " + q(png), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("frames/s"), std::string::npos) << r.out;
  int w = 0, h = 0, n = 0;
  unsigned char* px = stbi_load(png.c_str(), &w, &h, &n, 3);
  ASSERT_NE(px, nullptr) << "not a PNG: " << png;
  const int side = std::min(w, h);
  const double cx = 0.5 * side, cy = 0.5 * side, r_px = 0.45 * side;
  long lower = 0, upper = 0, outside = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const unsigned char* p = px + 3 * (static_cast<long>(y) * w + x);
      if (!(p[0] == 66 && p[1] == 135 && p[2] == 245)) continue;
      const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
      if (d > r_px + 1.0) ++outside;       // one pixel: the shell's own rasterisation
      else if (y + 0.5 > cy) ++lower;      // image rows grow downward
      else ++upper;
    }
  stbi_image_free(px);
  // The charge's solid area: filling 0.3 of the mill at a bulk packing of 0.8 (the lab
  // scene), in pixels. A disk's antialiased rim (one pixel: a sixth of a 12-pixel disk) and the
  // trails drawn over disks are not in the exact colour, so half of it is a safe floor; at
  // 0.75 of critical most of the charge lies below the centre.
  const double solid_px = 0.3 * 0.8 * M_PI * r_px * r_px;
  EXPECT_GT(lower + upper, 0.5 * solid_px) << "lower " << lower << " upper " << upper;
  EXPECT_GT(lower, 2 * upper) << "lower " << lower << " upper " << upper;
  EXPECT_EQ(outside, 0);
}

// 1.5 of critical: the charge rides round with the shell (the charge summary's definition
// reads it centrifuged); back at 0.75 it has a toe and a shoulder again; a larger filling
// adds disks and none escapes or goes non-finite.
TEST(View, ScriptCentrifugesCascadesAgainAndAddsFilling) {
  const TempDir dir("millwear-view-test-script");
  write(dir / "s.txt",
        "0 time_scale 3\n"   // 3/60 s simulated a frame: times below are a third of the simulated
        "0 speed 1.5\n"
        "2 report\n"
        "2 speed 0.75\n"
        "4 report\n"
        "4 filling 0.4 0.4\n"
        "5 report\n"
        "5 quit\n");
  const Result r = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " + q((dir / "s.txt").string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rep = reports(r.out);
  ASSERT_EQ(rep.size(), 3u) << r.out;
  EXPECT_EQ(rep[0].at("shape"), "centrifuged") << r.out;
  EXPECT_NE(rep[1].at("shape"), "centrifuged") << r.out;
  EXPECT_NE(rep[1].at("shape").find("toe"), std::string::npos) << r.out;
  // filling 0.4 of the same sizes: a third more disks (whole disks, a uniform size draw).
  EXPECT_NEAR(num(rep[2], "disks") / num(rep[1], "disks"), 0.4 / 0.3, 0.05) << r.out;
  for (const auto& f : rep) {
    EXPECT_EQ(num(f, "lost"), 0) << r.out;
    EXPECT_EQ(num(f, "finite"), 1) << r.out;
  }
}

// A value the scene checker refuses is refused with its message, and the run says so (exit 2);
// the message is the one `millwear charge` gives for a scene file with that value.
TEST(View, RefusesAValueWithTheCheckersMessage) {
  const TempDir dir("millwear-view-test-refuse");
  write(dir / "s.txt", "0 report\n0 filling 1.5\n0.5 report\n0.5 quit\n");
  const Result r = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " + q((dir / "s.txt").string()), dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  // The same value in a copy of the scene, checked by `millwear charge`.
  std::string text = slurp(kLab);
  const auto at = text.find("filling = 0.3 ");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 13, "filling = 1.5");
  const auto prof = text.find("../profiles/");
  text.replace(prof, 12, src("profiles/"));
  write(dir / "lab-mill.toml", text);
  const Result c = run_millwear("charge " + q((dir / "lab-mill.toml").string()) + " -o " + q((dir / "out").string()), dir);
  ASSERT_EQ(c.exit_code, 2);
  // "FILE: charge.filling: expected ..." -> the part after the file name.
  const std::string want = c.err.substr(c.err.find("charge.filling"));
  const std::string first_line = want.substr(0, want.find('\n'));
  EXPECT_NE(r.err.find(first_line), std::string::npos) << "view: " << r.err << "\ncharge: " << c.err;
  // The run ended at the refused line: the report before it ran, the one after it did not.
  const auto rep = reports(r.out);
  ASSERT_EQ(rep.size(), 1u) << r.out;
  EXPECT_GT(num(rep[0], "disks"), 100);
}

// Values past what the panel's controls allow are refused with the script's line before the
// window opens (a time scale of 1e9 hung the first frame; wear of 1e12 h overflowed a count).
TEST(View, ScriptValuesPastTheControlsAreRefusedBeforeTheWindow) {
  const TempDir dir("millwear-view-test-script-range");
  for (const std::string bad : {"0 time_scale 1e9", "0 time_scale 0", "0 trails 100000", "0 trails 2.5", "0 wear 1e12",
                                 "0 speed 0", "0 speed 2.5"}) {
    write(dir / "s.txt", "0 report\n" + bad + "\n1 quit\n");
    const Result r = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " + q((dir / "s.txt").string()), dir);
    EXPECT_EQ(r.exit_code, 2) << bad << "\n" << r.err;
    EXPECT_NE(r.err.find("line 2"), std::string::npos) << bad << "\n" << r.err;
    EXPECT_TRUE(reports(r.out).empty()) << bad << ": the window ran";
    // The speed's bounds are the slider's and the scene checker's (mill.speed), named.
    if (bad.find("speed") != std::string::npos) {
      EXPECT_NE(r.err.find("[0.01, 2]"), std::string::npos) << r.err;
    }
  }
  // A script saved with a byte-order mark reads.
  write(dir / "bom.txt", "\xEF\xBB\xBF" "0 report\n0 quit\n");
  const Result ok = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " + q((dir / "bom.txt").string()), dir);
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
}

// A script's files go into folders it names, made as a recording's are; a command that cannot
// do its work names the script's line.
TEST(View, ScriptFilesMakeTheirFoldersAndFailuresNameTheLine) {
  const TempDir dir("millwear-view-test-script-files");
  write(dir / "s.txt", "0.2 save_scene " + (dir / "out/edited.toml").string() + "\n0.2 screenshot " +
                          (dir / "shots/a.png").string() + "\n0.4 quit\n");
  const Result r = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " + q((dir / "s.txt").string()), dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(dir / "out/edited.toml"));
  EXPECT_TRUE(fs::exists(dir / "shots/a.png"));
  write(dir / "p.txt", "0 report\n0.2 save_profiles " + (dir / "prof").string() + "\n0.4 quit\n");
  const Result p = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " + q((dir / "p.txt").string()), dir);
  EXPECT_EQ(p.exit_code, 1) << p.err;
  EXPECT_NE(p.err.find("script line 2, save_profiles"), std::string::npos) << p.err;
}

// A scene save writes its edited lifter beside it as FILE_lifter.toml: a user's own file of
// that name is refused (exit 2, naming it and the script line) and stays as it was, with no
// scene written; a lifter an earlier save wrote there is the save's to replace.
TEST(View, ASceneSaveLeavesAUsersFileUnderItsLifterNameAlone) {
  const TempDir dir("millwear-view-test-lifter-name");
  write(dir / "mine_lifter.toml", "the user's own notes\n");
  write(dir / "s.txt", "0 lifter 25 20 25\n0 save_scene " + (dir / "mine.toml").string() + "\n0 quit\n");
  const Result r = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " + q((dir / "s.txt").string()), dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("mine_lifter.toml"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("script line 2, save_scene"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(dir / "mine_lifter.toml"), "the user's own notes\n");
  EXPECT_FALSE(fs::exists(dir / "mine.toml"));
  write(dir / "t.txt", "0 lifter 25 20 25\n0 save_scene " + (dir / "ours.toml").string() + "\n0 lifter 22 20 25\n0 save_scene " +
                          (dir / "ours.toml").string() + "\n0 quit\n");
  const Result again = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " + q((dir / "t.txt").string()), dir);
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(slurp(dir / "ours_lifter.toml").find("height = 22"), std::string::npos) << slurp(dir / "ours_lifter.toml");
}

// The power the view reads over its steady batches, and `millwear charge` on the scene the view
// saved, measure one process: they agree within four standard errors of their difference.
// The view's batch-means error is scaled to charge's shorter window for charge's own.
TEST(View, SavedScenesPowerMatchesTheReadout) {
  const TempDir dir("millwear-view-test-power");
  const std::string saved = (dir / "saved.toml").string();
  write(dir / "s.txt",
        "0 time_scale 4\n"   // 20 s simulated
        "0 speed 0.8\n"
        "5 report\n"
        "5 save_scene " + saved + "\n"
        "5 quit\n");
  const Result r = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " + q((dir / "s.txt").string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rep = reports(r.out);
  ASSERT_EQ(rep.size(), 1u) << r.out;
  const double p_view = num(rep[0], "steady_kW_per_m"), sem_view = num(rep[0], "steady_sem_kW_per_m");
  const double batches = num(rep[0], "steady_batches");
  ASSERT_GE(batches, 8) << r.out;
  ASSERT_GT(sem_view, 0.0);
  const double revs = 4.0;
  const Result c = run_millwear("charge " + q(saved) + " -o " + q((dir / "out").string()) + " --revolutions 4", dir);
  ASSERT_EQ(c.exit_code, 0) << c.err;
  const std::string csv = slurp(dir / "out" / "charge_summary.csv");
  const auto at = csv.find("power_per_m,");
  ASSERT_NE(at, std::string::npos) << csv;
  const double p_charge = std::strtod(csv.c_str() + at + 12, nullptr);
  const double sem_charge = sem_view * std::sqrt(0.5 * batches / revs);  // batches are half revolutions
  EXPECT_NEAR(p_view, p_charge, 4.0 * std::hypot(sem_view, sem_charge))
      << "view " << p_view << " +- " << sem_view << ", charge " << p_charge;
}

// Wear mode runs the scene's wear history: the profiles it draws are, byte for byte, the ones
// `millwear run` writes for the same scene and seed.
TEST(View, WearModeDrawsTheProfilesRunWrites) {
  const TempDir dir("millwear-view-test-wear");
  write(dir / "s.txt",
        "0 wear 200\n"
        "0 wait_wear\n"
        "0 save_profiles " + (dir / "view").string() + "\n"
        "0 quit\n");
  const Result r = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " + q((dir / "s.txt").string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Result run = run_millwear("run " + q(kLab) + " --fidelity draft -q -o " + q((dir / "run").string()), dir);
  ASSERT_EQ(run.exit_code, 0) << run.err;
  for (int k = 0; k <= 2; ++k) {
    const std::string name = "profiles/lab-mill_stage" + std::to_string(k) + ".csv";
    const std::string a = slurp(dir / "view" / name), b = slurp(dir / "run" / name);
    ASSERT_FALSE(b.empty()) << name;
    EXPECT_EQ(a, b) << name;
  }
  // The history wore the lifter: the last profile differs from the new one.
  EXPECT_NE(slurp(dir / "view" / "profiles/lab-mill_stage0.csv"), slurp(dir / "view" / "profiles/lab-mill_stage2.csv"));
}

// A reset while the wear mode runs is refused like the other controls (exit 2, naming the
// line), not passed over as if it had refilled the mill.
TEST(View, AResetWhileTheWearModeRunsIsRefused) {
  const TempDir dir("millwear-view-test-reset-wear");
  write(dir / "s.txt", "0 wear 200\n0 reset\n0 wait_wear\n0 reset\n0.2 quit\n");
  const Result r = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " + q((dir / "s.txt").string()), dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("refused at line 2: the wear mode is running"), std::string::npos) << r.err;
  // Once the history has finished, the reset is the mill's to do.
  EXPECT_EQ(r.err.find("refused at line 4"), std::string::npos) << r.err;
}

// The wear history's profiles are saved beside no command's results (a run's folder, whose
// profiles they would replace) and over no file of other points (a user's): both are refused,
// exit 2, naming the folder or file, which stay as they were. The same history saved twice
// into one folder is the same files.
TEST(View, SavedProfilesReplaceNoRunsAndNoUsersFiles) {
  const TempDir dir("millwear-view-test-profiles-taken");
  fs::create_directories(dir / "run" / "profiles");
  write(dir / "run" / "manifest.json", "{\"program\": \"millwear\", \"files\": [\"profiles/lab-mill_stage0.csv\"]}\n");
  write(dir / "run" / "profiles" / "lab-mill_stage0.csv", "x_mm,y_mm\n0,1\n");
  fs::create_directories(dir / "mine" / "profiles");
  write(dir / "mine" / "profiles" / "lab-mill_stage1.csv", "x_mm,y_mm\n0,2\n");
  for (const char* taken : {"run", "mine"}) {
    write(dir / "s.txt", "0 wear 100\n0 wait_wear\n0 save_profiles " + (dir / "ok").string() + "\n0 save_profiles " +
                            (dir / "ok").string() + "\n0 save_profiles " + (dir / taken).string() + "\n0 quit\n");
    const Result r = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " + q((dir / "s.txt").string()), dir);
    EXPECT_EQ(r.exit_code, 2) << taken << "\n" << r.err;
    EXPECT_NE(r.err.find((dir / taken).string()), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("script line 5, save_profiles"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::exists(dir / "ok" / "profiles" / "lab-mill_stage1.csv")) << r.err;
  }
  EXPECT_EQ(slurp(dir / "run" / "profiles" / "lab-mill_stage0.csv"), "x_mm,y_mm\n0,1\n");
  EXPECT_FALSE(fs::exists(dir / "run" / "profiles" / "lab-mill_stage1.csv"));
  EXPECT_EQ(slurp(dir / "mine" / "profiles" / "lab-mill_stage1.csv"), "x_mm,y_mm\n0,2\n");
  EXPECT_FALSE(fs::exists(dir / "mine" / "profiles" / "lab-mill_stage0.csv"));
}

// A recording starts in a folder without frames: a second recording into the folder of a first
// is refused (exit 2, naming the folder and the script line), so the first's frames are
// neither written over nor left behind the second's in the film made of the folder.
TEST(View, ARecordingIsNotMadeOverTheFramesOfAnother) {
  const TempDir dir("millwear-view-test-record-twice");
  const std::string frames = (dir / "frames").string();
  write(dir / "s.txt", "0 record " + frames + "\n0.2 stop_record\n0.3 record " + frames + "\n0.4 quit\n");
  const Result r = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " + q((dir / "s.txt").string()), dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(frames), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("script line 3, record"), std::string::npos) << r.err;
  int count = 0;
  for (const auto& e : fs::directory_iterator(frames)) count += e.path().extension() == ".png";
  EXPECT_GE(count, 12);  // 0 to 0.2 s of frames, 1/60 s each: the first recording's alone
  EXPECT_LE(count, 13);
}

// A scene with a pattern of lifters (hi-lo: one liner unit per kind, repeating over the rows)
// is drawn row by row from its kind's unit: the window opens, runs and writes its screenshot.
TEST(View, APatternOfLiftersIsDrawnFromEachRowsKind) {
  const TempDir dir("millwear-view-test-pattern");
  const std::string shot = (dir / "hi-lo.png").string();
  const Result r = run_millwear("view " + q(src("scenarios/lab-hi-lo.toml")) + " --fidelity draft --size 640 400 --frames 3 --screenshot " +
                                    q(shot), dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(shot)) << r.err;
}

// On a pattern scene a profile, or a lifter's height and faces, is every row's: it takes the
// pattern's place (it was refused, the scene then naming both keys), the mill is rebuilt with
// one kind, and the saved scene carries the one profile without the pattern or its comment.
TEST(View, AProfileOrALifterOnAPatternSceneIsEveryRowsAndIsSaved) {
  const TempDir dir("millwear-view-test-pattern-edit");
  const std::string saved = (dir / "one.toml").string(), shaped = (dir / "shaped.toml").string();
  write(dir / "s.txt",
        "0 profile " + src("profiles/lab-lo.toml") + "\n"
        "0.1 report\n"
        "0.1 save_scene " + saved + "\n"
        "0.2 lifter 18 25 25\n"
        "0.3 save_scene " + shaped + "\n"
        "0.3 quit\n");
  const Result r = run_millwear("view " + q(src("scenarios/lab-hi-lo.toml")) + " --fidelity draft --size 640 400 --script " +
                                    q((dir / "s.txt").string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_EQ(r.err.find("refused"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("lost=0 finite=1"), std::string::npos) << r.out;
  const std::string one = slurp(saved), lifter = slurp(dir / "shaped_lifter.toml");
  EXPECT_EQ(one.find("pattern"), std::string::npos) << one;
  EXPECT_EQ(one.find("kind k % 2"), std::string::npos) << one;
  EXPECT_NE(one.find("lab-lo.toml"), std::string::npos) << one;
  EXPECT_NE(slurp(shaped).find("profile = 'shaped_lifter.toml'"), std::string::npos) << slurp(shaped);
  EXPECT_NE(lifter.find("height = 18"), std::string::npos) << lifter;
  for (const std::string& scene : {saved, shaped}) {
    const Result check = run_millwear("run --check " + q(scene) + " -o " + q((dir / "out").string()), dir);
    EXPECT_EQ(check.exit_code, 0) << scene << "\n" << check.out << check.err;
  }
}

// The lifter's shape and the direction change in the running mill, and the saved scene carries
// them: `millwear run --check` accepts it, and its lifter file has the height set. A recording
// writes a frame sequence.
TEST(View, ShapeAndDirectionEditsAreSavedAsAScene) {
  const TempDir dir("millwear-view-test-edits");
  const std::string saved = (dir / "edited.toml").string();
  write(dir / "s.txt",
        "0 lifter 25 20 25\n"
        "0 direction reverse\n"
        "0 record " + (dir / "frames").string() + "\n"
        "0.5 stop_record\n"
        "1 report\n"
        "1 save_scene " + saved + "\n"
        "1 quit\n");
  const Result r = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " + q((dir / "s.txt").string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string scene = slurp(saved), lifter = slurp(dir / "edited_lifter.toml");
  EXPECT_NE(scene.find("direction = \"reverse\""), std::string::npos) << scene;
  EXPECT_EQ(scene.find("reverse_every ="), std::string::npos) << scene;  // one-way mills have none
  EXPECT_NE(scene.find("fidelity = \"draft\""), std::string::npos) << scene;
  EXPECT_NE(lifter.find("height = 25"), std::string::npos) << lifter;
  EXPECT_NE(lifter.find("leading_face_angle = 20"), std::string::npos) << lifter;
  // The recording: a PNG a frame from 0 to 0.5 s of frames (1/60 s each), 30 or 31 of them
  // as the stop falls.
  int frames = 0;
  for (const auto& e : fs::directory_iterator(dir / "frames")) frames += e.path().extension() == ".png";
  EXPECT_GE(frames, 30);
  EXPECT_LE(frames, 31);
  const Result check = run_millwear("run --check " + q(saved) + " -o " + q((dir / "out").string()), dir);
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
}

namespace {
// A copy of the lab scene in `dir` whose profile path points at the shipped profile.
fs::path lab_copy(const fs::path& dir, const std::string& name) {
  std::string text = slurp(kLab);
  const auto prof = text.find("../profiles/");
  text.replace(prof, 12, src("profiles/"));
  write(dir / name, text);
  return dir / name;
}
}  // namespace

// A scene save and a screenshot write over no file the view did not write: the scene on
// screen, the script being run and a user's own files are refused (exit 2, naming the file
// and the script's line, or --screenshot) and stay as they were.
TEST(View, ASceneSaveOrAScreenshotReplacesNoFileTheViewDidNotWrite) {
  const TempDir dir("millwear-view-test-not-ours");
  const std::string scene = (dir / "scene.toml").string(), script = (dir / "s.txt").string();
  const std::string notes = "the user's own notes\n";
  for (const std::string& line : {"0 save_scene " + scene, "0 screenshot " + scene, "0 save_scene " + script,
                                  "0 screenshot " + script, "0 screenshot " + (dir / "notes.png").string(),
                                  "0 save_scene " + (dir / "notes.toml").string()}) {
    // Each case from the same files: the scene, the script and the user's notes.
    const std::string scene_text = slurp(lab_copy(dir, "scene.toml"));
    write(dir / "notes.png", notes);
    write(dir / "notes.toml", notes);
    const std::string text = "0 report\n" + line + "\n0.2 quit\n";
    write(script, text);
    const Result r = run_millwear("view " + q(scene) + " --size 640 400 --script " + q(script), dir);
    EXPECT_EQ(r.exit_code, 2) << line << "\n" << r.err;
    const std::string target = line.substr(line.rfind(' ') + 1);
    EXPECT_NE(r.err.find(target), std::string::npos) << line << "\n" << r.err;
    EXPECT_NE(r.err.find("script line 2"), std::string::npos) << line << "\n" << r.err;
    EXPECT_EQ(slurp(script), text) << line;
    EXPECT_EQ(slurp(scene), scene_text) << line;
    EXPECT_EQ(slurp(dir / "notes.png"), notes) << line;
    EXPECT_EQ(slurp(dir / "notes.toml"), notes) << line;
  }
  // --screenshot: refused before the window opens.
  const Result shot = run_millwear("view " + q(scene) + " --size 640 400 --frames 2 --screenshot " +
                                       q((dir / "notes.png").string()), dir);
  EXPECT_EQ(shot.exit_code, 2) << shot.err;
  EXPECT_NE(shot.err.find((dir / "notes.png").string()), std::string::npos) << shot.err;
  EXPECT_EQ(slurp(dir / "notes.png"), notes);
}

// The files the view wrote are its own to write again: a script run twice, and --screenshot
// given twice, write the same names both times.
TEST(View, TheFilesAScriptWroteAreWrittenAgainWhenItRunsAgain) {
  const TempDir dir("millwear-view-test-run-again");
  const std::string saved = (dir / "saved.toml").string(), shot = (dir / "shot.png").string();
  write(dir / "s.txt", "0 lifter 25 20 25\n0.1 save_scene " + saved + "\n0.1 screenshot " + shot +
                           "\n0.2 screenshot " + shot + "\n0.2 quit\n");
  for (int run = 0; run < 2; ++run) {
    const Result r = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " +
                                      q((dir / "s.txt").string()) + " --screenshot " + q((dir / "end.png").string()),
                                  dir);
    EXPECT_EQ(r.exit_code, 0) << "run " << run << "\n" << r.err;
  }
  EXPECT_TRUE(fs::exists(dir / "saved_lifter.toml"));
  int w = 0, h = 0, n = 0;
  for (const std::string& png : {shot, (dir / "end.png").string()}) {
    unsigned char* px = stbi_load(png.c_str(), &w, &h, &n, 3);
    EXPECT_NE(px, nullptr) << "not a PNG: " << png;
    stbi_image_free(px);
  }
  const Result check = run_millwear("run --check " + q(saved) + " -o " + q((dir / "out").string()), dir);
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
}

// A pattern scene saved into another folder names its pattern's profiles from there (as it
// names a single profile): `millwear run --check` accepts the saved scene.
TEST(View, APatternSceneSavedIntoAnotherFolderNamesItsProfilesFromThere) {
  const TempDir dir("millwear-view-test-pattern-save");
  const std::string saved = (dir / "sub" / "hi-lo.toml").string();
  write(dir / "s.txt", "0 speed 0.8\n0 save_scene " + saved + "\n0.1 quit\n");
  const Result r = run_millwear("view " + q(src("scenarios/lab-hi-lo.toml")) + " --fidelity draft --size 640 400 --script " +
                                    q((dir / "s.txt").string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string text = slurp(saved);
  EXPECT_NE(text.find("pattern = ["), std::string::npos) << text;
  EXPECT_NE(text.find("row k: kind k % 2"), std::string::npos) << text;  // the line's comment stays
  const Result check = run_millwear("run --check " + q(saved) + " -o " + q((dir / "out").string()), dir);
  EXPECT_EQ(check.exit_code, 0) << check.out << check.err;
}

// A control refused while a script runs ends the run at its line (exit 2): no later line runs
// and nothing more is written, --screenshot's last frame included.
TEST(View, AScriptStopsAtARefusedControl) {
  const TempDir dir("millwear-view-test-stop");
  write(dir / "s.txt", "0 report\n0 filling 1.5\n1 save_scene " + (dir / "after.toml").string() + "\n1 screenshot " +
                           (dir / "after.png").string() + "\n2 report\n2 quit\n");
  const Result r = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " + q((dir / "s.txt").string()) +
                                    " --screenshot " + q((dir / "end.png").string()),
                                dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("refused at line 2"), std::string::npos) << r.err;
  EXPECT_EQ(reports(r.out).size(), 1u) << r.out;
  EXPECT_FALSE(fs::exists(dir / "after.toml"));
  EXPECT_FALSE(fs::exists(dir / "after.png"));
  EXPECT_FALSE(fs::exists(dir / "end.png"));
}

// A lifter shape the checker refuses is named by the values the line gave, where the refusal
// named the view's temporary lifter file and the scene's profile line.
TEST(View, ARefusedLifterShapeIsNamedByItsValues) {
  const TempDir dir("millwear-view-test-lifter");
  write(dir / "s.txt", "0 lifter 20 -10 30\n0.1 quit\n");
  const Result r = run_millwear("view " + q(kLab) + " --size 640 400 --script " + q((dir / "s.txt").string()), dir);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("refused at line 1: lifter 20 -10 30: leading_face_angle: expected"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("millwear-view-"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("the profile named by"), std::string::npos) << r.err;
}

// Screenshots asked for at one script time are each written, each of the frame after the
// lines before it: only the last of a frame's was.
TEST(View, EveryScreenshotOfAScriptTimeIsWritten) {
  const TempDir dir("millwear-view-test-shots");
  const auto png = [&](const char* f) { return (dir / f).string(); };
  write(dir / "s.txt", "0.05 screenshot " + png("c1.png") + "\n0.05 screenshot " + png("c2.png") + "\n0.05 pause\n" +
                           "0.05 screenshot " + png("c3.png") + "\n0.1 screenshot " + png("c4.png") + "\n0.1 quit\n");
  const Result r = run_millwear("view " + q(kLab) + " --size 640 400 --script " + q((dir / "s.txt").string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* f : {"c1.png", "c2.png", "c3.png", "c4.png"}) EXPECT_TRUE(fs::exists(dir / f)) << f << r.err;
}

// After a change the steady mean takes the batches that began one revolution (the lab scene's
// spin-up) after it, not those that only ended then: the one that straddles that time holds
// half a revolution of the transient.
TEST(View, TheSteadyMeanLeavesOutEveryBatchThatBeganInTheTransient) {
  const TempDir dir("millwear-view-test-steady");
  write(dir / "s.txt", "0 time_scale 4\n1.5 speed 0.9\n2.5 report\n2.5 quit\n");  // the change at 6 s
  const Result r = run_millwear("view " + q(kLab) + " --size 640 400 --script " + q((dir / "s.txt").string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rep = reports(r.out);
  ASSERT_EQ(rep.size(), 1u) << r.out;
  ASSERT_EQ(num(rep[0], "t"), 10.0) << r.out;
  // The lab mill, 0.6 m across, at 0.9 of critical: a revolution of 2 pi / (0.9 sqrt(g / 0.3 m)),
  // batches of half of it from the change on.
  const double revolution_s = 2.0 * M_PI / (0.9 * std::sqrt(9.81 / 0.3));
  const int closed = static_cast<int>(std::floor(4.0 / (0.5 * revolution_s)));  // 6 in the 4 s since
  EXPECT_EQ(num(rep[0], "steady_batches"), closed - 2) << r.out;
}

// A report gives nan for what is not measured yet: the power before the first batch, the
// steady mean before its first batch, its standard error under two batches. Every field
// stays key=value.
TEST(View, AReportGivesNanForWhatIsNotMeasuredYet) {
  const TempDir dir("millwear-view-test-report-nan");
  std::string script;
  for (int k = 0; k <= 14; ++k) script += std::to_string(0.25 * k) + " report\n";
  write(dir / "s.txt", script + "3.5 quit\n");
  const Result r = run_millwear("view " + q(kLab) + " --fidelity draft --size 640 400 --script " + q((dir / "s.txt").string()), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto rep = reports(r.out);
  ASSERT_EQ(rep.size(), 15u) << r.out;
  int unread = 0, one_batch = 0, more = 0;
  for (const auto& f : rep) {
    const double batches = num(f, "steady_batches");
    if (f.at("shape") == "no readout yet") {
      ++unread;
      EXPECT_TRUE(std::isnan(num(f, "power_kW_per_m"))) << r.out;
    } else {
      EXPECT_GT(num(f, "power_kW_per_m"), 0.0) << r.out;
    }
    if (batches == 0) EXPECT_TRUE(std::isnan(num(f, "steady_kW_per_m"))) << r.out;
    else EXPECT_GT(num(f, "steady_kW_per_m"), 0.0) << r.out;
    if (batches < 2) {
      EXPECT_TRUE(std::isnan(num(f, "steady_sem_kW_per_m"))) << r.out;
    } else {
      EXPECT_GT(num(f, "steady_sem_kW_per_m"), 0.0) << r.out;
      ++more;
    }
    one_batch += batches == 1;
  }
  // The lab mill settles 0.5 s, turns a revolution (1.47 s at 0.75 of critical) before its
  // steady window, then closes a batch every half revolution: 3.5 s sees all three cases.
  EXPECT_GT(unread, 0) << r.out;
  EXPECT_GT(one_batch, 0) << r.out;
  EXPECT_GT(more, 0) << r.out;
}
