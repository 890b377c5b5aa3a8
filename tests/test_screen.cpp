// `millwear screen` end to end on a small lab-mill family (tests/data/screen-lab.toml: 4
// designs, draft fidelity, one stage), and the screen module's pieces (sampling, life
// uncertainty, ties, Pareto fronts).
//
// One local screen with --jobs 2 is the reference, shared by every test of the suite (cached
// next to the test binary while the binary and the input files are unchanged, like
// test_app_run's run). The same ranking.csv, byte for byte, must come out of --jobs 1, GNU
// parallel and a real Slurm job array; the GNU parallel and Slurm tests skip with a message
// (never pass) when the packages are missing. Copies of the reference test --resume (only an
// unfinished design runs again) and the live progress line (on a pseudo-terminal); a 2 x 2
// face-angle family tests the heat map.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_support.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/folder_lock.hpp"
#include "metrics/pareto.hpp"
#include "plots/plots.hpp"
#include "profiles/profile.hpp"
#include "scene/scene.hpp"
#include "screen/jobs.hpp"
#include "screen/ranking.hpp"
#include "screen/screen.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using millwear::testing::TempDir;
using namespace millwear;
using namespace millwear::screen;

namespace {

using Result = millwear::testing::CliResult;
constexpr auto shell = &millwear::testing::run_shell;

std::string q(const fs::path& p) { return "'" + p.string() + "'"; }
Result millwear_cmd(const std::string& args) { return shell(q(MILLWEAR_BINARY) + " " + args); }

std::string src(const std::string& rel) { return std::string(MILLWEAR_SOURCE_DIR) + "/" + rel; }

constexpr auto slurp = &millwear::testing::read_text;

bool have(const std::string& exe) { return shell("command -v " + exe + " >/dev/null").exit_code == 0; }

const char* kScreen = "tests/data/screen-lab.toml";

std::string stamp() {
  std::string s;
  for (const std::string& f : {std::string(MILLWEAR_BINARY), src(kScreen), src("scenarios/lab-mill.toml"),
                               src("profiles/lab-2x30.toml")}) {
    std::error_code ec;
    s += f + " " + std::to_string(fs::file_size(f, ec)) + " " +
         std::to_string(fs::last_write_time(f, ec).time_since_epoch().count()) + "\n";
  }
  return s;
}

}  // namespace

class ScreenRun : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    root_ = fs::temp_directory_path() / ("millwear-test-screen-" + std::to_string(::getpid()));
    fs::remove_all(root_);
    fs::create_directories(root_);
    const fs::path cache = fs::path(MILLWEAR_BINARY).parent_path() / "test_screen_cache";
    fs::create_directories(cache);
    ref_ = cache / "jobs2";
    const int lock = ::open((cache / "lock").c_str(), O_CREAT | O_RDWR, 0644);
    if (lock >= 0) ::flock(lock, LOCK_EX);
    const std::string st = stamp();
    if (fs::exists(ref_ / "ranking.csv") && slurp(cache / "stamp") == st) {
      ref_result_.exit_code = 0;
    } else {
      fs::remove_all(ref_);
      ref_result_ = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(ref_) + " --jobs 2 --quiet");
      if (ref_result_.exit_code == 0) std::ofstream(cache / "stamp") << st;
    }
    if (lock >= 0) ::close(lock);
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  void SetUp() override { ASSERT_EQ(ref_result_.exit_code, 0) << ref_result_.output; }

  // The finished screen copied to OUT without design d002 and the ranking; then
  // `screen-task OUT 2` started, sent `sig` once it has written its task.status and run
  // `after_ms` more, and waited for. Its wait status.
  static int task_two_stopped(const fs::path& out, int sig, int after_ms) {
    fs::copy(ref_, out, fs::copy_options::recursive);
    fs::remove_all(out / "designs/d002");
    fs::remove(out / "ranking.csv");
    const pid_t pid = ::fork();
    if (pid == 0) {
      const int null = ::open("/dev/null", O_WRONLY);
      ::dup2(null, 1);
      ::dup2(null, 2);
      ::execl(MILLWEAR_BINARY, MILLWEAR_BINARY, "screen-task", out.c_str(), "2", static_cast<char*>(nullptr));
      ::_exit(127);
    }
    if (pid < 0) {
      ADD_FAILURE() << "fork failed";
      return 0;
    }
    for (int i = 0; i < 100 && !fs::exists(out / "designs/d002/task.status"); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    std::this_thread::sleep_for(std::chrono::milliseconds(after_ms));
    ::kill(pid, sig);
    int status = 0;
    ::waitpid(pid, &status, 0);
    return status;
  }

  static fs::path root_, ref_;
  static Result ref_result_;
};
fs::path ScreenRun::root_, ScreenRun::ref_;
Result ScreenRun::ref_result_;

TEST_F(ScreenRun, RanksEveryDesignAndWritesTheFiles) {
  const io::CsvData r = io::read_csv((ref_ / "ranking.csv").string());
  ASSERT_EQ(r.row_count(), 4u);
  for (std::size_t i = 0; i < r.row_count(); ++i) {
    EXPECT_EQ(r.text(i, r.column("status")), "finished");
    EXPECT_EQ(r.number(i, "rank"), double(i + 1));
    EXPECT_GT(r.number(i, "life_h"), 0.0);
    EXPECT_GT(r.number(i, "life_sigma_h"), 0.0);  // every draft window has batch-means noise
    // The life's error is the one `millwear run` gives the design.
    const std::string name = r.text(i, r.column("design"));
    const io::CsvData sum = io::read_csv((ref_ / "designs" / name / "summary.csv").string());
    EXPECT_EQ(r.number(i, "life_sigma_h"), sum.number(0, "life_h_se")) << name;
    if (i > 0) {
      EXPECT_LE(r.number(i, "life_h"), r.number(i - 1, "life_h"));
    }
  }
  EXPECT_EQ(r.number(0, "tied_with_best"), 1.0);  // the best is tied with itself
  EXPECT_EQ(r.number(0, "pareto_utilization"), 1.0);  // the longest life is always on a front
  EXPECT_EQ(r.number(0, "pareto_power"), 1.0);
  // Each candidate's folder is a `millwear run` folder.
  for (const char* f : {"designs.csv", "rejected.csv", "candidates/d000.toml", "candidates/d000-profile.toml",
                        "designs/d000/summary.csv", "designs/d000/manifest.json", "designs/d000/profiles/d000_stage1.csv",
                        "designs/d000/plots/fig7_area.png", "designs/d000/task.status"})
    EXPECT_TRUE(fs::exists(ref_ / f)) << f;
  if (have("gnuplot")) {
    for (const char* f : {"plots/screen_pareto.png", "plots/screen_pareto.svg", "plots/screen_top_profiles.png"})
      EXPECT_GT(fs::file_size(ref_ / f), 1000u) << f;
  }
  // equal_area = "base": every candidate has the lab 2x30's area (431 mm^2), to 1e-9 relative.
  const io::CsvData d = io::read_csv((ref_ / "designs.csv").string());
  for (std::size_t i = 0; i < d.row_count(); ++i) EXPECT_NEAR(d.number(i, "area_mm2"), 430.9401, 1e-3);
}

TEST_F(ScreenRun, RankingIsIdenticalWithOneJob) {
  const fs::path out = root_ / "jobs1";
  const Result r = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) + " --jobs 1 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(slurp(out / "ranking.csv"), slurp(ref_ / "ranking.csv"));
}

TEST_F(ScreenRun, RankingIsIdenticalThroughGnuParallel) {
  if (!have("parallel")) GTEST_SKIP() << "GNU parallel is not installed (apt-get install parallel): not tested";
  // A folder whose name means something to the shell: the commands the screen prints run as
  // pasted (N set to 2).
  const fs::path out = root_ / "it's $HOME parallel";
  const std::string quoted_out = "'" + root_.string() + "/it'\\''s $HOME parallel'";
  Result r = millwear_cmd("screen " + q(src(kScreen)) + " -o " + quoted_out + " --emit parallel");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(out / "jobs.txt"));
  const auto printed = [&r](const std::string& lead) {
    const auto at = r.output.find(lead);
    return at == std::string::npos ? std::string() : r.output.substr(at + lead.size(), r.output.find('\n', at) - at - lead.size());
  };
  std::string run = printed("run:  "), then = printed("then: ");
  ASSERT_EQ(run.rfind("parallel -j N < ", 0), 0u) << r.output;
  run.replace(run.find(" N "), 3, " 2 ");
  r = shell(run.replace(0, 8, "parallel --will-cite"));
  ASSERT_EQ(r.exit_code, 0) << run << "\n" << r.output;
  r = shell(then);
  ASSERT_EQ(r.exit_code, 0) << then << "\n" << r.output;
  EXPECT_EQ(slurp(out / "ranking.csv"), slurp(ref_ / "ranking.csv"));
}

// Figure scripts that are not there: every history finishes and is ranked as with figures,
// each task.status says finished with exit code 1 and why, and the screen exits 1 (0 on a
// machine without gnuplot, where figures are not expected). A figure's failure is not a
// design's: none is marked failed, and all are ranked.
TEST_F(ScreenRun, FiguresThatFailLeaveEveryDesignRankedAndExitOne) {
  const fs::path out = root_ / "no-scripts", scripts = root_ / "no-scripts-plots";
  fs::create_directories(scripts);
  const Result r = shell("MILLWEAR_PLOTS_DIR=" + q(scripts) + " " + q(MILLWEAR_BINARY) + " screen " + q(src(kScreen)) +
                         " -o " + q(out) + " --jobs 2 --quiet");
  const bool gnuplot = plots::gnuplot_available();
  EXPECT_EQ(r.exit_code, gnuplot ? 1 : 0) << r.output;
  EXPECT_EQ(slurp(out / "ranking.csv"), slurp(ref_ / "ranking.csv")) << r.output;
  const io::CsvData rank = io::read_csv((out / "ranking.csv").string());
  ASSERT_EQ(rank.row_count(), 4u);
  for (std::size_t i = 0; i < rank.row_count(); ++i) {
    const std::string name = rank.text(i, rank.column("design"));
    const std::string status = slurp(out / "designs" / name / "task.status");
    EXPECT_NE(status.find("status=finished"), std::string::npos) << name << ": " << status;
    if (!gnuplot) continue;
    EXPECT_NE(status.find("exit_code=1"), std::string::npos) << name << ": " << status;
    EXPECT_NE(status.find("figures failed"), std::string::npos) << name << ": " << status;
    EXPECT_NE(r.output.find("design " + name + ": figures failed"), std::string::npos) << r.output;
  }
  if (!gnuplot) return;
  // With the scripts back, --resume redraws them: each task runs again over its finished history.
  const Result again = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) + " --jobs 2 --quiet --resume");
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(slurp(out / "ranking.csv"), slurp(ref_ / "ranking.csv"));
  for (std::size_t i = 0; i < rank.row_count(); ++i) {
    const std::string name = rank.text(i, rank.column("design"));
    EXPECT_NE(slurp(out / "designs" / name / "task.status").find("exit_code=0"), std::string::npos) << name;
  }
}

// --replicates N: every task runs N histories (seeds s .. s + N - 1) through `millwear run`'s
// path; the life's sigma is the standard error of their mean, which for two histories is half
// their difference; replicate 1 is the plain screen's history, bit for bit.
TEST_F(ScreenRun, ReplicatesGiveTheLifeErrorFromTheSpreadOfTheHistories) {
  const fs::path out = root_ / "replicates";
  Result r = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) + " --jobs 2 --quiet --replicates 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("standard error of the mean of 2 replicates"), std::string::npos) << r.output;
  // The legend states the tie rule the ranking used: Student's t for two histories, not 2 sigma.
  EXPECT_NE(r.output.find("not resolved by Student's t for 2 replicates"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("within 2 combined sigma"), std::string::npos) << r.output;
  EXPECT_NE(slurp(out / "screen.key").find("\nreplicates=2\n"), std::string::npos);
  const io::CsvData rank = io::read_csv((out / "ranking.csv").string());
  const io::CsvData ref = io::read_csv((ref_ / "ranking.csv").string());
  ASSERT_EQ(rank.row_count(), 4u);
  for (std::size_t i = 0; i < rank.row_count(); ++i) {
    const std::string name = rank.text(i, rank.column("design"));
    EXPECT_EQ(rank.number(i, "replicates"), 2.0) << name;
    EXPECT_EQ(rank.text(i, rank.column("error_source")), "replicates") << name;
    // The two histories, from the design's replicates.csv.
    const io::CsvData h = io::read_csv((out / "designs" / name / "replicates.csv").string());
    double life[3] = {std::nan(""), std::nan(""), std::nan("")};
    for (std::size_t k = 0; k < h.row_count(); ++k)
      if (h.number(k, "stage") == 0.0) life[static_cast<int>(h.number(k, "replicate"))] = h.number(k, "life_h");
    ASSERT_TRUE(std::isfinite(life[1]) && std::isfinite(life[2])) << name;
    EXPECT_NE(life[1], life[2]) << name;  // different seeds, different histories
    EXPECT_NEAR(rank.number(i, "life_h"), 0.5 * (life[1] + life[2]), 1e-6 * life[1]) << name;
    EXPECT_NEAR(rank.number(i, "life_sigma_h"), 0.5 * std::fabs(life[1] - life[2]), 1e-6 * life[1]) << name;
    // Replicate 1 is the plain screen's history.
    for (std::size_t j = 0; j < ref.row_count(); ++j)
      if (ref.text(j, ref.column("design")) == name) {
        EXPECT_EQ(ref.text(j, ref.column("error_source")), "batch_means");
        EXPECT_EQ(ref.number(j, "replicates"), 1.0);
        EXPECT_NEAR(life[1], ref.number(j, "life_h"), 1e-6 * life[1]) << name;
      }
  }
  // Resuming with another number of replicates would mix two screens in one folder.
  r = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) + " --resume --quiet --replicates 3");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--replicates"), std::string::npos) << r.output;
  r = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(root_ / "bad") + " --replicates 0");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_FALSE(fs::exists(root_ / "bad"));
}

// Stops the private Slurm on every way out of the test.
struct SlurmGuard {
  fs::path dir;
  ~SlurmGuard() {
    if (!dir.empty()) shell(q(src("tests/slurm/stop_slurm.sh")) + " " + q(dir));
  }
};

TEST_F(ScreenRun, RankingIsIdenticalThroughASlurmJobArray) {
  for (const char* exe : {"munged", "slurmctld", "slurmd", "sbatch", "squeue"})
    if (!have(exe)) GTEST_SKIP() << exe << " is not installed (apt-get install slurm-wlm munge): Slurm not tested";
  const fs::path dir = root_ / "slurm-daemons";
  SlurmGuard guard{dir};
  Result r = shell(q(src("tests/slurm/start_slurm.sh")) + " " + q(dir));
  ASSERT_EQ(r.exit_code, 0) << "could not start a private Slurm:\n" << r.output;
  const std::string env = "SLURM_CONF=" + q(dir / "slurm.conf") + " ";

  // A folder with a space and a % in its name: the task logs go into it all the same.
  const fs::path out = root_ / "slurm 100%";
  r = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) + " --emit slurm --chunk 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(slurp(out / "screen.sbatch").find("#SBATCH --array=0-1"), std::string::npos);  // 4 designs, 2 a task
  r = shell(env + "sbatch --parsable " + q(out / "screen.sbatch"));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Accounting is off (no sacct): poll squeue until the array has left the queue.
  const auto t0 = std::chrono::steady_clock::now();
  for (;;) {
    r = shell(env + "squeue -h -o %i");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    if (r.output.find_first_not_of(" \n") == std::string::npos) break;
    ASSERT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(600)) << "the array did not finish";
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  r = millwear_cmd("screen --collect " + q(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(slurp(out / "ranking.csv"), slurp(ref_ / "ranking.csv"));
  EXPECT_TRUE(fs::exists(out / "slurm/tasks.txt"));
  // Each of the two array tasks logged its screen-task's output there.
  int logs = 0;
  for (const auto& e : fs::directory_iterator(out / "slurm"))
    if (e.path().filename().string().rfind("task-", 0) == 0 && e.path().extension() == ".out") {
      ++logs;
      EXPECT_NE(slurp(e.path()).find("d00"), std::string::npos) << e.path();
    }
  EXPECT_EQ(logs, 2);
}

// A task stopped by Ctrl-C writes `interrupted` in its task.status: --collect reports it as
// missing with that reason, where it called the status unknown.
TEST_F(ScreenRun, AnInterruptedTaskIsReportedMissingWithItsReason) {
  const fs::path out = root_ / "interrupted";
  const int status = task_two_stopped(out, SIGINT, 300);
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 130) << "the task finished before it was stopped";
  ASSERT_NE(slurp(out / "designs/d002/task.status").find("status=interrupted"), std::string::npos);
  const Result r = millwear_cmd("screen --collect " + q(out));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("design d002 missing"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("run it again to continue"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("unknown task status"), std::string::npos) << r.output;
}

TEST_F(ScreenRun, KilledTaskIsReportedMissingAndRerunCompletesTheRanking) {
  const fs::path out = root_ / "killed";
  // Task 2 killed (SIGKILL: no chance to clean up) while it runs.
  const int status = task_two_stopped(out, SIGKILL, 500);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the task finished before it was killed";

  Result r = millwear_cmd("screen --collect " + q(out));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("design d002 missing"), std::string::npos) << r.output;
  for (const char* other : {"d000 missing", "d001 missing", "d003 missing", "failed:"})
    EXPECT_EQ(r.output.find(other), std::string::npos) << other << "\n" << r.output;
  const io::CsvData partial = io::read_csv((out / "ranking.csv").string());
  ASSERT_EQ(partial.row_count(), 4u);
  EXPECT_EQ(partial.text(3, partial.column("design")), "d002");
  EXPECT_EQ(partial.text(3, partial.column("status")), "missing");

  // --emit re-emits only the missing design.
  r = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) + " --emit parallel");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string jobs = slurp(out / "jobs.txt");
  EXPECT_EQ(std::count(jobs.begin(), jobs.end(), '\n'), 1) << jobs;
  EXPECT_NE(jobs.find("screen-task '" + out.string() + "' 2\n"), std::string::npos) << jobs;

  r = millwear_cmd("screen-task " + q(out) + " 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = millwear_cmd("screen --collect " + q(out));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(slurp(out / "ranking.csv"), slurp(ref_ / "ranking.csv"));
}

// A task of several designs runs each of them whatever the others did: a candidate made
// unreadable is that design's (exit 2 at the end), where the task stopped at it and left the
// designs after it never run.
TEST_F(ScreenRun, ATaskOfSeveralDesignsRunsThoseAfterOneThatIsRefused) {
  const fs::path out = root_ / "chunk";
  Result r = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) + " --emit parallel --chunk 3");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path bad = out / "candidates" / "d001.toml";
  std::string text = slurp(bad);
  const auto at = text.find("\nspeed = ");
  ASSERT_NE(at, std::string::npos) << text;
  text.replace(at + 1, text.find('\n', at + 1) - at - 1, "speed = 5.0");
  std::ofstream(bad, std::ios::binary) << text;
  r = millwear_cmd("screen-task " + q(out) + " 0 1 2");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  for (const char* d : {"d000", "d002"})
    EXPECT_NE(slurp(out / "designs" / d / "task.status").find("finished"), std::string::npos) << d << "\n" << r.output;
}

// Task numbers are checked before any task runs: an empty one (an unset array index) is not
// task 0, and a bad one after a good one runs neither.
TEST_F(ScreenRun, TaskNumbersAreCheckedBeforeAnyTaskRuns) {
  const fs::path out = root_ / "tasks";
  fs::copy(ref_, out, fs::copy_options::recursive);
  const std::string status = slurp(out / "designs/d000/task.status");
  for (const std::string& args : {std::string("''"), std::string("0 99"), std::string("0 x")}) {
    const Result r = millwear_cmd("screen-task " + q(out) + " " + args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_EQ(slurp(out / "designs/d000/task.status"), status) << args << ": task 0 ran";
  }
}

// A finished design whose results went missing is failed with the file named as it lies in
// OUT, so the ranking is the same bytes whatever OUT was called on the command line; the
// reason says the file is not there (it said "a readable file").
TEST_F(ScreenRun, AFinishedDesignsLostResultsAreNamedWithinTheScreensFolder) {
  const fs::path out = root_ / "lost";
  fs::copy(ref_, out, fs::copy_options::recursive);
  fs::remove(out / "designs" / "d000" / "summary.csv");
  Result r = shell("cd " + q(root_) + " && " + q(MILLWEAR_BINARY) + " screen --collect lost");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  const std::string relative = slurp(out / "ranking.csv");
  EXPECT_NE(relative.find("results unreadable: designs/d000/summary.csv: a file there (not found)"), std::string::npos)
      << relative;
  r = millwear_cmd("screen --collect " + q(out));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_EQ(slurp(out / "ranking.csv"), relative);
  // The command to finish it names a folder with a space as one shell word.
  const fs::path spaced = root_ / "lost results";
  fs::copy(out, spaced, fs::copy_options::recursive);
  r = millwear_cmd("screen --collect " + q(spaced));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("millwear screen-task '" + spaced.string() + "' I"), std::string::npos) << r.output;
}

// A damaged designs.csv is refused naming it; the ranking already there is left as it was.
TEST_F(ScreenRun, CollectRefusesADamagedDesignsListAndKeepsTheRanking) {
  const fs::path out = root_ / "damaged";
  fs::copy(ref_, out, fs::copy_options::recursive);
  const std::string ranking = slurp(out / "ranking.csv");
  const std::string header = slurp(out / "designs.csv").substr(0, slurp(out / "designs.csv").find('\n') + 1);
  for (const std::string& text : {std::string("hello\x01world\n"), header}) {
    std::ofstream(out / "designs.csv", std::ios::binary) << text;
    const Result r = millwear_cmd("screen --collect " + q(out));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("designs.csv"), std::string::npos) << r.output;
    EXPECT_EQ(slurp(out / "ranking.csv"), ranking);
  }
}

// designs.csv edited by hand (its last rows cut, a value changed) was collected as a smaller
// screen, or ranked a design against another's values, with exit 0. Its hash is in
// screen.key: --collect and the tasks refuse a changed list, naming it, and --resume writes
// it anew.
TEST_F(ScreenRun, ADesignsListChangedByHandIsRefusedAndResumeWritesItAnew) {
  const fs::path out = root_ / "edited";
  fs::copy(ref_, out, fs::copy_options::recursive);
  const std::string list = slurp(out / "designs.csv"), ranking = slurp(out / "ranking.csv");
  const std::string cut = list.substr(0, list.find('\n', list.find('\n') + 1) + 1);  // header and d000
  std::string edited = list;
  const std::string own = "candidates/d000-profile";  // d000 given d001's profile
  ASSERT_NE(edited.find(own), std::string::npos) << list;
  edited.replace(edited.find(own), own.size(), "candidates/d001-profile");
  for (const std::string& text : {cut, edited}) {
    std::ofstream(out / "designs.csv", std::ios::binary) << text;
    for (const std::string& command : {"screen --collect " + q(out), "screen-task " + q(out) + " 0"}) {
      const Result r = millwear_cmd(command);
      EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.output;
      EXPECT_NE(r.output.find("designs.csv: the list of designs this screen wrote"), std::string::npos) << r.output;
    }
    EXPECT_EQ(slurp(out / "ranking.csv"), ranking);
  }
  const Result again = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) + " --jobs 2 --resume --quiet");
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_EQ(slurp(out / "designs.csv"), list);
  EXPECT_EQ(slurp(out / "ranking.csv"), ranking);
}

// A finished design whose summary's new-liner power reads nan (a damaged table) was ranked
// as finished with nan power; it is a design whose results are unreadable.
TEST_F(ScreenRun, ADesignWhosePowerReadsNanIsNotRanked) {
  const fs::path out = root_ / "nan-power";
  fs::copy(ref_, out, fs::copy_options::recursive);
  const io::CsvData summary = io::read_csv((out / "designs/d001/summary.csv").string());
  const std::string text = slurp(out / "designs/d001/summary.csv");
  const std::string power = summary.text(0, summary.column("power_kw"));
  const std::size_t second_line = text.find('\n') + 1;
  const std::size_t at = text.find("," + power + ",", second_line);
  ASSERT_NE(at, std::string::npos) << text;
  std::string damaged = text;
  damaged.replace(at + 1, power.size(), "nan");
  std::ofstream(out / "designs/d001/summary.csv", std::ios::binary) << damaged;
  const Result r = millwear_cmd("screen --collect " + q(out));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("results unreadable"), std::string::npos) << r.output;
  const io::CsvData ranking = io::read_csv((out / "ranking.csv").string());
  bool listed = false;
  for (std::size_t i = 0; i < ranking.row_count(); ++i)
    if (ranking.text(i, ranking.column("design")) == "d001") {
      listed = true;
      EXPECT_EQ(ranking.text(i, ranking.column("status")), "failed");
    }
  EXPECT_TRUE(listed) << slurp(out / "ranking.csv");
}

namespace {

// Every regular file under dir (relative path) with its modification time.
std::map<std::string, fs::file_time_type> file_times(const fs::path& dir) {
  std::map<std::string, fs::file_time_type> t;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) t[fs::relative(e.path(), dir).string()] = e.last_write_time();
  return t;
}

std::set<std::string> file_names(const fs::path& dir) {
  std::set<std::string> s;
  if (fs::exists(dir))
    for (const auto& e : fs::directory_iterator(dir)) s.insert(e.path().filename().string());
  return s;
}

// `millwear ARGS` with stdout and stderr on a pseudo-terminal, as in a user's terminal (the
// screen's live progress line is drawn only when stderr is a terminal). Output as the
// terminal received it (\r, \x1b[K and \r\n included).
Result millwear_on_tty(const std::vector<std::string>& args) {
  Result r;
  const int master = ::posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0) return r;
  if (::grantpt(master) != 0 || ::unlockpt(master) != 0 || ::ptsname(master) == nullptr) {
    ::close(master);
    return r;
  }
  ::fcntl(master, F_SETFD, FD_CLOEXEC);
  const std::string slave = ::ptsname(master);
  std::vector<char*> argv{const_cast<char*>(MILLWEAR_BINARY)};
  for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(master);
    return r;
  }
  if (pid == 0) {
    ::setsid();
    const int s = ::open(slave.c_str(), O_RDWR);
    const int null = ::open("/dev/null", O_RDONLY);
    if (s < 0 || null < 0) ::_exit(127);
    ::dup2(null, 0);
    ::dup2(s, 1);
    ::dup2(s, 2);
    ::execv(MILLWEAR_BINARY, argv.data());
    ::_exit(127);
  }
  char buf[4096];
  for (;;) {
    const ssize_t n = ::read(master, buf, sizeof buf);
    if (n > 0) r.output.append(buf, static_cast<std::size_t>(n));
    else if (n < 0 && errno == EINTR) continue;
    else break;  // EIO: the program and its tasks have closed the terminal
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  ::close(master);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

struct ProgressLine {
  int done = -1, total = -1, running = -1, failed = -1;
  std::string elapsed, left;
};

// The progress lines a terminal showed, in order (each redraw after \r\x1b[K is one line).
std::vector<ProgressLine> progress_lines(const std::string& tty) {
  static const std::regex re(
      R"(screen: (\d+)/(\d+) done, (\d+) running, (\d+) failed, elapsed (\S+), left (\S+))");
  std::vector<ProgressLine> v;
  std::string seg;
  auto flush = [&] {
    std::smatch m;
    if (std::regex_search(seg, m, re))
      v.push_back({std::stoi(m[1]), std::stoi(m[2]), std::stoi(m[3]), std::stoi(m[4]), m[5], m[6]});
    seg.clear();
  };
  for (char c : tty) {
    if (c == '\r' || c == '\n') flush();
    else seg += c;
  }
  flush();
  return v;
}

}  // namespace

TEST_F(ScreenRun, ResumeRunsOnlyTheUnfinishedDesignAndGivesTheSameRanking) {
  // A design is finished when designs/NAME/task.status says status=finished: take one design's
  // folder away (and the pool's task logs, which every spawned task rewrites).
  const fs::path out = root_ / "resume";
  fs::copy(ref_, out, fs::copy_options::recursive);
  fs::remove_all(out / "designs/d001");
  fs::remove_all(out / "logs");
  const auto before = file_times(out / "designs");
  ASSERT_FALSE(before.empty());

  const Result r = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) + " --jobs 2 --resume --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Only d001 was started again: one task log, and the other designs' files are untouched.
  EXPECT_EQ(file_names(out / "logs"), (std::set<std::string>{"d001.log"}));
  auto after = file_times(out / "designs");
  for (auto it = after.begin(); it != after.end();)
    it = it->first.rfind("d001/", 0) == 0 ? after.erase(it) : std::next(it);
  std::string touched;  // files of the finished designs that disappeared, appeared or were rewritten
  for (const auto& [f, t] : before)
    if (!after.count(f) || !(after.at(f) == t)) touched += f + "\n";
  for (const auto& [f, t] : after)
    if (!before.count(f)) touched += f + " (new)\n";
  EXPECT_EQ(touched, "");
  EXPECT_NE(slurp(out / "designs/d001/task.status").find("status=finished"), std::string::npos);
  EXPECT_EQ(slurp(out / "ranking.csv"), slurp(ref_ / "ranking.csv"));
}

// A design whose task.status says finished but whose summary.csv is gone (its results
// unreadable, as --collect says) is run again by --resume, which gives the same ranking; it
// was counted finished, and --resume failed on it every time.
TEST_F(ScreenRun, ResumeRunsAgainAFinishedDesignWhoseResultsAreUnreadable) {
  const fs::path out = root_ / "unreadable";
  fs::copy(ref_, out, fs::copy_options::recursive);
  fs::remove(out / "designs/d001/summary.csv");
  fs::remove_all(out / "logs");
  const Result r = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) + " --jobs 2 --resume --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(file_names(out / "logs"), (std::set<std::string>{"d001.log"}));
  EXPECT_EQ(slurp(out / "ranking.csv"), slurp(ref_ / "ranking.csv"));
}

// A folder holding a screen of other inputs is refused, and with --force that screen's files
// (only those) are deleted first: a user's own files in the folder and its subfolders stay.
TEST_F(ScreenRun, AnotherScreensFolderIsReplacedOnlyWithForceAndTheUsersFilesStay) {
  const fs::path out = root_ / "replaced";
  fs::copy(ref_, out, fs::copy_options::recursive);
  const std::map<std::string, std::string> mine = {{"designs/d000/my-notes.txt", "a"},
                                                   {"designs/d000/mine/a.txt", "b"},
                                                   {"designs/my-designs.txt", "c"},
                                                   {"candidates/my-candidate.toml", "d"},
                                                   {"logs/my.log", "e"},
                                                   {"plots/my-figure.png", "f"},
                                                   {"candidates/d000-notes.txt", "g"},
                                                   {"logs/d001-mine.log", "h"}};
  for (const auto& [f, text] : mine) {
    fs::create_directories((out / f).parent_path());
    std::ofstream(out / f) << text;
  }
  const auto before = file_times(out);
  const std::string other = "screen " + q(src(kScreen)) + " -o " + q(out) + " --set mill.speed=0.7 --jobs 2 --quiet";
  Result r = millwear_cmd(other);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--force"), std::string::npos) << r.output;
  EXPECT_TRUE(file_times(out) == before) << "a refused screen changes nothing";

  r = millwear_cmd(other + " --force");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const auto& [f, text] : mine) EXPECT_EQ(slurp(out / f), text) << f;
  EXPECT_EQ(load_scene((out / "candidates/d000.toml").string()).mill.speed_fraction_critical, 0.7);
  const auto m = nlohmann::json::parse(slurp(out / "designs/d000/manifest.json"));
  EXPECT_EQ(m["designs"][0]["settings"]["mill"]["speed_fraction_critical"].get<double>(), 0.7);
}

TEST_F(ScreenRun, ProgressOnATerminalCountsDoneRunningFailedAndTimeLeft) {
  // Resume with two designs to run, one at a time: d000 cannot write its folder (a file has
  // its name) and fails at once, d003 runs. Without a terminal the pool draws no progress
  // line (docs/screen.md: "On a terminal one line shows ..."), so the run gets a pseudo-terminal.
  const fs::path out = root_ / "progress";
  fs::copy(ref_, out, fs::copy_options::recursive);
  fs::remove_all(out / "designs/d000");
  std::ofstream(out / "designs/d000") << "not a folder\n";
  fs::remove_all(out / "designs/d003");
  const int total = static_cast<int>(io::read_csv((out / "designs.csv").string()).row_count());
  ASSERT_EQ(total, 4);

  const Result r = millwear_on_tty({"screen", src(kScreen), "-o", out.string(), "--jobs", "1", "--resume"});
  EXPECT_EQ(r.exit_code, 1) << r.output;  // d000 failed: not every design is ranked
  EXPECT_NE(r.output.find("4 design(s), 2 to run, 1 job(s)"), std::string::npos) << r.output;
  const std::vector<ProgressLine> lines = progress_lines(r.output);
  ASSERT_FALSE(lines.empty()) << "no progress line on a terminal:\n" << r.output;
  bool saw_running = false, saw_estimate = false;
  for (const auto& l : lines) {
    EXPECT_EQ(l.total, total);
    EXPECT_LE(l.done + l.running + l.failed, total);
    EXPECT_LE(l.running, 1);  // --jobs 1
    saw_running |= l.running == 1;
    // Once a design has ended (here d000) while d003 runs, a time left is shown ("--" before).
    saw_estimate |= l.running == 1 && l.failed == 1 && l.left != "--";
  }
  EXPECT_TRUE(saw_running) << r.output;
  EXPECT_TRUE(saw_estimate) << r.output;
  // The last line: every design accounted for, nothing running.
  const ProgressLine& last = lines.back();
  EXPECT_EQ(last.done, total - 1) << r.output;
  EXPECT_EQ(last.failed, 1) << r.output;
  EXPECT_EQ(last.running, 0) << r.output;
  EXPECT_EQ(last.done + last.failed, total);
  EXPECT_EQ(last.left, "0s") << r.output;
  EXPECT_NE(slurp(out / "designs/d003/task.status").find("status=finished"), std::string::npos);
}

TEST_F(ScreenRun, HeatMapOfLifeForATwoParameterFamily) {
  // The lab screen varies one parameter only: no heat map there.
  EXPECT_FALSE(fs::exists(ref_ / "plots/screen_heatmap.png"));
  EXPECT_FALSE(fs::exists(ref_ / "plots/data/heatmap.dat"));
  if (!have("gnuplot"))
    GTEST_SKIP() << "gnuplot is not installed: the screen draws no figures (and writes no heat-map data)";
  // The lab screen with two varying face angles: a 2 x 2 grid, 4 designs.
  const fs::path dir = root_ / "heatmap";
  const fs::path f = dir / "screen-lab-2d.toml";
  fs::create_directories(dir);
  std::ofstream(f) << "[screen]\nname = \"lab-two-angles\"\nbase = '" << src("scenarios/lab-mill.toml")
                   << "'\nfidelity = \"draft\"\nstages = 1\nsampling = \"grid\"\nequal_area = \"base\"\n"
                      "[family]\nheight = 20.0\nleading_face_angle = [10.0, 30.0]\n"
                      "trailing_face_angle = [20.0, 40.0]\ndirection = \"uni\"\n";
  const fs::path out = dir / "out";
  const Result r = millwear_cmd("screen " + q(f) + " -o " + q(out) + " --jobs 2 --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.output;

  EXPECT_EQ(slurp(out / "plots/screen_heatmap.png").rfind("\x89PNG\r\n", 0), 0u);
  EXPECT_GT(fs::file_size(out / "plots/screen_heatmap.png"), 1000u);
  EXPECT_NE(slurp(out / "plots/screen_heatmap.svg").find("<svg"), std::string::npos);
  EXPECT_GT(fs::file_size(out / "plots/screen_heatmap.svg"), 1000u);

  // heatmap.dat: x (leading), y (trailing), life_h, design; one row per grid cell.
  const io::CsvData designs = io::read_csv((out / "designs.csv").string());
  const io::CsvData ranking = io::read_csv((out / "ranking.csv").string());
  ASSERT_EQ(designs.row_count(), 4u);
  ASSERT_EQ(ranking.row_count(), 4u);
  std::set<std::pair<double, double>> cells;
  std::set<std::string> named;
  std::size_t rows = 0;
  std::istringstream dat(slurp(out / "plots/data/heatmap.dat"));
  for (std::string line; std::getline(dat, line);) {
    if (line.empty()) continue;
    ++rows;
    std::istringstream in(line);
    std::string x, y, life, name;
    ASSERT_TRUE(std::getline(in, x, ',') && std::getline(in, y, ',') && std::getline(in, life, ',') &&
                std::getline(in, name))
        << line;
    cells.insert({std::stod(x), std::stod(y)});
    named.insert(name);
    std::size_t di = designs.row_count(), ri = ranking.row_count();
    for (std::size_t i = 0; i < designs.row_count(); ++i)
      if (designs.text(i, designs.column("design")) == name) di = i;
    for (std::size_t i = 0; i < ranking.row_count(); ++i)
      if (ranking.text(i, ranking.column("design")) == name) ri = i;
    ASSERT_LT(di, designs.row_count()) << name;
    ASSERT_LT(ri, ranking.row_count()) << name;
    // heatmap.dat and ranking.csv are both written to 10 significant digits: relative 1e-9.
    EXPECT_NEAR(std::stod(x), designs.number(di, "leading_face_angle_deg"), 1e-9 * std::abs(std::stod(x))) << line;
    EXPECT_NEAR(std::stod(y), designs.number(di, "trailing_face_angle_deg"), 1e-9 * std::abs(std::stod(y))) << line;
    const double life_h = ranking.number(ri, "life_h");
    EXPECT_GT(life_h, 0.0);
    EXPECT_NEAR(std::stod(life), life_h, 1e-9 * life_h) << line;
  }
  EXPECT_EQ(rows, 4u);
  EXPECT_EQ(named.size(), 4u);
  EXPECT_EQ(cells, (std::set<std::pair<double, double>>{{10, 20}, {10, 40}, {30, 20}, {30, 40}}));
}

// ---------------------------------------------------------------------------------------
// Bad input: exit 2, a clear message, nothing run.

namespace {
fs::path write_screen(const fs::path& dir, const std::string& name, const std::string& text) {
  fs::create_directories(dir);
  const fs::path p = dir / name;
  std::ofstream(p) << text;
  return p;
}
std::string lab_base() { return src("scenarios/lab-mill.toml"); }
}  // namespace

TEST(ScreenInput, UnknownKeyExitsTwoNamingFileKeyAndLine) {
  const TempDir dir("millwear-screen-bad");
  const fs::path f = write_screen(dir, "bad.toml",
                                  "[screen]\nbase = '" + lab_base() + "'\n[family]\nheigth = 20.0\n");
  const Result r = millwear_cmd("screen " + q(f) + " -o " + q(dir / "out"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad.toml: family.heigth: unknown key (did you mean 'height'?)"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(line 4)"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out"));  // nothing written before validation passes
}

TEST(ScreenInput, BadValueExitsTwoWithTheExpectation) {
  const TempDir dir("millwear-screen-bad2");
  const fs::path f = write_screen(dir, "bad.toml",
                                  "[screen]\nbase = '" + lab_base() +
                                      "'\n[family]\nleading_face_angle = {min = 10.0, max = 95.0, steps = 3}\n");
  Result r = millwear_cmd("screen " + q(f) + " -o " + q(dir / "out"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("family.leading_face_angle.max: expected a number in [0, 90)"), std::string::npos) << r.output;
  // A range without steps in a grid.
  const fs::path g = write_screen(dir, "grid.toml",
                                  "[screen]\nbase = '" + lab_base() + "'\n[family]\nheight = {min = 10.0, max = 20.0}\n");
  r = millwear_cmd("screen " + q(g) + " -o " + q(dir / "out"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("family.height.steps"), std::string::npos) << r.output;
  // A missing base scene.
  const fs::path m = write_screen(dir, "nobase.toml", "[screen]\nbase = 'nowhere.toml'\n");
  r = millwear_cmd("screen " + q(m) + " -o " + q(dir / "out"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("screen.base"), std::string::npos) << r.output;
  // A value given twice would make every candidate with it twice.
  for (const auto& [family, says] : std::vector<std::pair<std::string, std::string>>{
           {"leading_face_angle = [10.0, 20.0, 10.0]",
            "family.leading_face_angle[2]: expected each value once, got 10 again (as family.leading_face_angle[0])"},
           {"height = 20.0\ndirection = ['uni', 'uni']", "family.direction[1]: expected each direction once"}}) {
    const fs::path t = write_screen(dir, "twice.toml", "[screen]\nbase = '" + lab_base() + "'\n[family]\n" + family + "\n");
    r = millwear_cmd("screen " + q(t) + " -o " + q(dir / "out"));
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(says), std::string::npos) << r.output;
  }
  // Stages shorter than a scene's are the screen file's own error (they were blamed on the
  // candidates' scenes, at a line of a file never written).
  const fs::path shortstage = write_screen(dir, "short.toml", "[screen]\nbase = '" + lab_base() +
                                                                  "'\nsampling = 'grid'\nstage_hours = 0.5\n");
  r = millwear_cmd("screen " + q(shortstage) + " -o " + q(dir / "out") + " --emit parallel");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("short.toml: screen.stage_hours: expected a number in [1,"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("(line 4)"), std::string::npos) << r.output;
  // A profile file and a copy of it elsewhere are one design twice.
  fs::create_directories(dir / "pa");
  fs::create_directories(dir / "pb");
  for (const char* sub : {"pa", "pb"})
    std::ofstream(dir / sub / "p.toml") << slurp(src("profiles/lab-2x30.toml"));
  const fs::path copies = write_screen(dir, "copies.toml", "[screen]\nbase = '" + lab_base() +
                                                               "'\n[family]\nprofiles = ['pa/p.toml', 'pb/p.toml']\n");
  r = millwear_cmd("screen " + q(copies) + " -o " + q(dir / "out") + " --emit parallel");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("family.profiles[1]: expected each profile once, but"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("the same candidates twice"), std::string::npos) << r.output;
  // A Latin hypercube of five samples over two listed angles draws one design several times.
  const fs::path lhs = write_screen(dir, "lhs.toml",
                                    "[screen]\nbase = '" + lab_base() +
                                        "'\nsampling = 'latin_hypercube'\nsamples = 5\n[family]\n"
                                        "leading_face_angle = [20.0, 30.0]\n");
  r = millwear_cmd("screen " + q(lhs) + " -o " + q(dir / "out") + " --emit parallel");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("screen.samples: samples that are each another design, but d00"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "out" / "jobs.txt"));
}

TEST(ScreenInput, FamilyWithNoValidCandidateExitsTwo) {
  // The lab mill is 600 mm across: a lifter of 160 mm or more reaches past half the radius
  // (radial faces and a 10 mm top, so the base fits the 157 mm pitch and height is the fault).
  const TempDir dir("millwear-screen-none");
  const fs::path f = write_screen(dir, "tall.toml",
                                  "[screen]\nbase = '" + lab_base() + "'\n[family]\nheight = [160.0, 200.0]\n"
                                  "top_width = 10.0\nleading_face_angle = 0.0\ntrailing_face_angle = 0.0\n");
  const Result r = millwear_cmd("screen " + q(f) + " -o " + q(dir / "out"));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("at least one valid candidate; all 2 were rejected"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("half the mill radius"), std::string::npos) << r.output;  // the first reason
  // A refusal writes nothing: the candidate files it wrote to check them are taken back.
  std::error_code ec;
  for (auto it = fs::recursive_directory_iterator(dir / "out", ec); !ec && it != fs::recursive_directory_iterator();
       ++it)
    EXPECT_FALSE(it->is_regular_file()) << "left behind: " << it->path();
}

TEST(ScreenInput, CandidatesThatCannotBeBuiltAreRejectedWithTheReason) {
  // 12 rows fit the 33 mm lab lifter; at 60 rows the pitch (31 mm) is narrower than its base;
  // equal area with a 60/60 deg trapezoid of 20 mm has no positive top width (faces alone: 693 mm^2).
  const TempDir dir("millwear-screen-rej");
  const fs::path f = write_screen(dir, "mixed.toml",
                                  "[screen]\nbase = '" + lab_base() + "'\nequal_area = 'base'\n"
                                  "[family]\nrows = [12, 60]\nleading_face_angle = [30.0, 60.0]\nsymmetric = true\n");
  const Result r = millwear_cmd("screen " + q(f) + " -o " + q(dir / "out") + " --emit parallel");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const io::CsvData good = io::read_csv((dir / "out/designs.csv").string());
  const io::CsvData bad = io::read_csv((dir / "out/rejected.csv").string());
  ASSERT_EQ(good.row_count(), 1u);
  EXPECT_EQ(good.text(0, good.column("design")), "d000");  // 30 deg, 12 rows
  ASSERT_EQ(bad.row_count(), 3u);
  EXPECT_NE(bad.text(0, bad.column("reason")).find("lifters.rows"), std::string::npos) << bad.text(0, bad.column("reason"));
  EXPECT_NE(bad.text(1, bad.column("reason")).find("positive top width"), std::string::npos);
}

// A measured scan in the list of profiles is a candidate like a drawn one: copied as a CSV (as
// TOML it would not read), its scene valid; a scan too thin for the charge is rejected.
TEST(ScreenInput, AMeasuredScanInTheListOfProfilesIsACandidate) {
  const TempDir dir("millwear-screen-csv");
  std::ofstream(dir / "fin.csv") << "x_mm,y_mm\n-20,-1\n-0.1,0\n0,20\n0.1,0\n20,-1\n";
  const fs::path f = write_screen(dir, "scans.toml",
                                  "[screen]\nbase = '" + lab_base() + "'\n[family]\nprofiles = ['" +
                                      src("profiles/lab-survey-2000h.csv") + "', 'fin.csv']\n");
  const Result r = millwear_cmd("screen " + q(f) + " -o " + q(dir / "out") + " --emit parallel");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const io::CsvData good = io::read_csv((dir / "out/designs.csv").string());
  const io::CsvData bad = io::read_csv((dir / "out/rejected.csv").string());
  ASSERT_EQ(good.row_count(), 1u);
  EXPECT_EQ(good.text(0, good.column("profile_file")), "candidates/d000-profile.csv");
  const Scene s = load_scene((dir / "out" / good.text(0, good.column("scene_file"))).string());
  EXPECT_FALSE(s.mill.lifter.measured.empty());
  ASSERT_EQ(bad.row_count(), 1u);
  EXPECT_NE(bad.text(0, bad.column("reason")).find("thinner than the particles"), std::string::npos)
      << bad.text(0, bad.column("reason"));
}

// A base that starts from a worn liner measured at 2,000 h: a drawn candidate is a new lifter
// and starts at 0 h (its life had the base's 2,000 h added); a listed measured scan keeps them.
TEST(ScreenInput, ADrawnCandidateOfAWornStartBaseStartsNew) {
  const TempDir dir("millwear-screen-worn-base");
  const fs::path f = write_screen(dir, "worn.toml",
                                  "[screen]\nbase = '" + src("scenarios/lab-worn-start.toml") +
                                      "'\nsampling = 'grid'\nequal_area = 'base'\n[family]\nheight = 18.0\n"
                                      "leading_face_angle = [20.0, 30.0]\ntrailing_face_angle = 30.0\n");
  Result r = millwear_cmd("screen " + q(f) + " -o " + q(dir / "out") + " --emit parallel");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const io::CsvData good = io::read_csv((dir / "out/designs.csv").string());
  ASSERT_EQ(good.row_count(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    const Scene s = load_scene((dir / "out" / good.text(i, good.column("scene_file"))).string());
    EXPECT_EQ(s.wear.start_hours, 0.0) << i;
  }
  const fs::path g = write_screen(dir, "scan.toml",
                                  "[screen]\nbase = '" + src("scenarios/lab-worn-start.toml") + "'\n[family]\nprofiles = ['" +
                                      src("profiles/lab-survey-2000h.csv") + "']\n");
  r = millwear_cmd("screen " + q(g) + " -o " + q(dir / "scan") + " --emit parallel");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const io::CsvData scan = io::read_csv((dir / "scan/designs.csv").string());
  ASSERT_EQ(scan.row_count(), 1u);
  EXPECT_EQ(load_scene((dir / "scan" / scan.text(0, scan.column("scene_file"))).string()).wear.start_hours, 2000.0);
}

// direction = ["uni", "bi"] over a history shorter than the reversal period: the bi design
// never reverses and ran byte for byte as the uni one, ranked as another. It is rejected with
// the reason; one that reverses within its history is a candidate.
TEST(ScreenInput, ABiDesignThatNeverReversesWithinItsHistoryIsRejected) {
  const TempDir dir("millwear-screen-never-reverses");
  // The base runs one way; a bi candidate reverses every 750 h (the default).
  for (const auto& [hours, bi_kept] : std::vector<std::pair<std::string, bool>>{{"10.0", false}, {"400.0", true}}) {
    const fs::path f = write_screen(dir, "dir.toml",
                                    "[screen]\nbase = '" + src("tests/data/lab-quick.toml") + "'\nsampling = 'grid'\n"
                                    "stages = 2\nstage_hours = " + hours + "\n[family]\ndirection = ['uni', 'bi']\n"
                                    "height = 20.0\n");
    const fs::path out = dir / ("out" + hours);
    const Result r = millwear_cmd("screen " + q(f) + " -o " + q(out) + " --emit parallel");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const io::CsvData good = io::read_csv((out / "designs.csv").string());
    EXPECT_EQ(good.row_count(), bi_kept ? 2u : 1u) << hours;
    if (!bi_kept) {
      const io::CsvData bad = io::read_csv((out / "rejected.csv").string());
      ASSERT_EQ(bad.row_count(), 1u);
      EXPECT_EQ(bad.text(0, bad.column("direction")), "bi");
      EXPECT_NE(bad.text(0, bad.column("reason")).find("never reverses"), std::string::npos)
          << bad.text(0, bad.column("reason"));
    }
  }
}

// A folder of a screen whose file changed since is refused naming that file's contents as
// what changed (it said only that one of the screen file, base scene or profiles, or the
// version did); another screen file of other contents is named then and now.
TEST(ScreenSet, AFolderOfAScreenWhoseFileChangedNamesTheFile) {
  const TempDir dir("millwear-screen-changed");
  const fs::path out = dir / "out", screen = dir / "screen.toml", other = dir / "other.toml";
  std::string text = slurp(src(kScreen));
  const std::string base = "\"../../scenarios/lab-mill.toml\"";
  text.replace(text.find(base), base.size(), "\"" + src("scenarios/lab-mill.toml") + "\"");
  std::ofstream(screen, std::ios::binary) << text;
  Result r = millwear_cmd("screen " + q(screen) + " -o " + q(out) + " --emit parallel");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ofstream(screen, std::ios::binary) << text + "\n# a note\n";
  r = millwear_cmd("screen " + q(screen) + " -o " + q(out) + " --emit parallel");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("(the contents of " + screen.string() + " changed)"), std::string::npos) << r.output;
  std::ofstream(other, std::ios::binary) << text + "\n# another note\n";
  r = millwear_cmd("screen " + q(other) + " -o " + q(out) + " --emit parallel");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("input 1 (" + screen.string() + " then, " + other.string() + " now)"), std::string::npos)
      << r.output;
}

// --set KEY=VALUE over the base scene: in every candidate's scene file (what the pool, GNU
// parallel and Slurm tasks read), recorded in screen.key, part of the fingerprint; a task run
// from the emitted list runs the overridden scene.
TEST(ScreenSet, OverridesReachEveryCandidateAndTheTasks) {
  const TempDir dir("millwear-screen-set");
  const fs::path out = dir / "out";
  Result r = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) +
                          " --emit parallel --set mill.speed=0.6 --set charge.species[0].density=7000");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const io::CsvData d = io::read_csv((out / "designs.csv").string());
  ASSERT_EQ(d.row_count(), 4u);
  const Scene base = load_scene(src("scenarios/lab-mill.toml"));
  ASSERT_EQ(base.mill.speed_fraction_critical, 0.75);  // the base file's own
  for (std::size_t i = 0; i < d.row_count(); ++i) {
    const Scene c = load_scene((out / d.text(i, d.column("scene_file"))).string());
    EXPECT_EQ(c.mill.speed_fraction_critical, 0.6) << i;
    EXPECT_EQ(c.charge.species[0].density_kg_m3, 7000.0) << i;
    EXPECT_EQ(c.charge.filling, base.charge.filling) << i;  // the rest is the base scene's
    EXPECT_NE(slurp(out / d.text(i, d.column("scene_file"))).find("--set mill.speed=0.6"), std::string::npos);
  }
  const std::string key = slurp(out / "screen.key");
  EXPECT_NE(key.find("set=mill.speed=0.6\nset=charge.species[0].density=7000\n"), std::string::npos) << key;
  // Emitting again with other overrides before any task ran is refused as well: the first
  // list may be queued, and its tasks would run the new scenes.
  r = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) + " --emit parallel --set mill.speed=0.7");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("(--set overrides changed)"), std::string::npos) << r.output;
  EXPECT_EQ(load_scene((out / "candidates/d000.toml").string()).mill.speed_fraction_critical, 0.6);  // untouched
  EXPECT_EQ(slurp(out / "screen.key"), key);
  // The task GNU parallel would run: the design's run folder records the overridden speed.
  r = millwear_cmd("screen-task " + q(out) + " 0");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto m = nlohmann::json::parse(slurp(out / "designs/d000/manifest.json"));
  EXPECT_EQ(m["designs"][0]["settings"]["mill"]["speed_fraction_critical"].get<double>(), 0.6);
  // Emitting the rest with other overrides would mix two screens in one folder: refused.
  r = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) + " --emit parallel --set mill.speed=0.7");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--set overrides"), std::string::npos) << r.output;
  EXPECT_EQ(load_scene((out / "candidates/d001.toml").string()).mill.speed_fraction_critical, 0.6);  // untouched
}

TEST(ScreenSet, BadOverrideExitsTwoNamingTheKeyBeforeAnythingIsWritten) {
  const TempDir dir("millwear-screen-badset");
  const fs::path out = dir / "out";
  struct Case {
    std::string set;
    std::vector<std::string> expect;
  };
  for (const Case& c : std::vector<Case>{
           {"mill.sped=0.8", {"--set mill.sped=0.8", "unknown key"}},   // a typo
           {"mill.speed=fast", {"--set mill.speed=fast", "mill.speed"}},  // a word for a number
           {"charge.filling=2", {"--set charge.filling=2", "charge.filling"}},  // out of range
           // Keys the screen sets for every candidate itself (the lab screen gives a direction).
           {"lifters.profile=x.toml", {"--set lifters.profile", "the family makes every candidate's lifter"}},
           {"mill.direction=forward", {"--set mill.direction", "family.direction sets it"}},
           {"name=mine", {"--set name"}},
       }) {
    const Result r =
        millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) + " --emit parallel --set " + q(c.set));
    EXPECT_EQ(r.exit_code, 2) << c.set << "\n" << r.output;
    for (const std::string& e : c.expect) EXPECT_NE(r.output.find(e), std::string::npos) << c.set << "\n" << r.output;
    EXPECT_FALSE(fs::exists(out)) << c.set;  // nothing written
  }
}

// A screen started over a folder where a task still runs a design (a GNU parallel job, say)
// is refused naming the holder, and removes nothing: a fresh start that cleared every
// design's files would clear the running task's too.
TEST(ScreenSet, AFreshScreenOverADesignATaskStillRunsIsRefusedAndRemovesNothing) {
  const TempDir dir("millwear-screen-held");
  const fs::path out = dir / "out";
  Result r = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) + " --emit parallel");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path design = out / "designs" / "d000";
  const io::FolderLock task((design).string());
  fs::create_directories(design / "profiles");
  io::write_file_atomic((design / "profiles" / "d000_stage0.csv").string(), "x_mm,y_mm\n0,0\n");
  r = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) + " --jobs 1 --quiet");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("process " + std::to_string(::getpid())), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("holds this design"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(design / "profiles" / "d000_stage0.csv"));
  EXPECT_TRUE(fs::exists(out / "jobs.txt"));
}

// Replicates take the seeds s .. s + N - 1: a seed at the top of the range with --replicates 2
// is refused before anything is written (it was a job list of tasks bound to fail).
TEST(ScreenSet, ReplicatesPastTheLastSeedExitTwoBeforeAnythingIsWritten) {
  const TempDir dir("millwear-screen-seed");
  const fs::path out = dir / "out";
  const Result r = millwear_cmd("screen " + q(src(kScreen)) + " -o " + q(out) +
                                " --emit parallel --replicates 2 --set solver.seed=9223372036854775807");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("solver.seed"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("--replicates 2"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out));
}

// A base scene with a hi-lo pattern: each candidate keeps the pattern, each kind a trapezoid
// with the family's face angle and its own height, its top width chosen for its own area.
TEST(ScreenPattern, EqualAreaMatchesEachKindToItsOwnArea) {
  const TempDir dir("millwear-screen-hilo");
  const std::string lab = src("profiles/lab-2x30.toml");
  std::ofstream(dir / "lo.toml") << "name = \"lab-lo\"\nform = \"trapezoid\"\nheight = 12.0\ntop_width = 10.0\n"
                                    "leading_face_angle = 30.0\ntrailing_face_angle = 30.0\n";
  // The lab mill with a pattern in place of its profile.
  std::string base = slurp(src("scenarios/lab-mill.toml"));
  const std::string prof_line = "profile = \"../profiles/lab-2x30.toml\"";
  ASSERT_NE(base.find(prof_line), std::string::npos);
  base.replace(base.find(prof_line), prof_line.size(), "pattern = ['" + lab + "', 'lo.toml']");
  std::ofstream(dir / "hilo.toml") << base;
  const auto screen = [&](const std::string& name, const std::string& equal_area) {
    return write_screen(dir, name,
                        "[screen]\nbase = 'hilo.toml'\nfidelity = 'draft'\nstages = 1\nequal_area = " + equal_area +
                            "\n[family]\nleading_face_angle = [10.0, 40.0]\ndirection = 'uni'\n");
  };
  const double hi_area = measure_profile(load_profile(lab).points).area_m2 * 1e6;
  const double lo_area = measure_profile(load_profile((dir / "lo.toml").string()).points).area_m2 * 1e6;

  // "base": each kind to its own kind's area.
  Result r = millwear_cmd("screen " + q(screen("base.toml", "'base'")) + " -o " + q(dir / "base") + " --emit parallel");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  io::CsvData d = io::read_csv((dir / "base/designs.csv").string());
  ASSERT_EQ(d.row_count(), 2u);
  for (std::size_t i = 0; i < d.row_count(); ++i) {
    // Each kind keeps its own height and trailing face (mm and degrees through metres and
    // radians: equal to rounding).
    EXPECT_NEAR(d.number(i, "kind0_height_mm"), 20.0, 1e-12);
    EXPECT_NEAR(d.number(i, "kind1_height_mm"), 12.0, 1e-12);
    EXPECT_NEAR(d.number(i, "kind1_trailing_face_angle_deg"), 30.0, 1e-12);
    EXPECT_EQ(d.number(i, "kind0_leading_face_angle_deg"), d.number(i, "kind1_leading_face_angle_deg"));
    // The written trapezoids, read back by the scene loader, have the target areas: the top
    // width is a closed form (profiles/profile.cpp top_width_for_area) written exactly, so
    // only rounding separates them (1e-9 relative).
    const Scene c = load_scene((dir / "base" / d.text(i, d.column("scene_file"))).string());
    ASSERT_EQ(c.mill.kind_count(), 2);
    EXPECT_NEAR(measure_profile(c.mill.kind(0).points).area_m2 * 1e6, hi_area, 1e-9 * hi_area) << i;
    EXPECT_NEAR(measure_profile(c.mill.kind(1).points).area_m2 * 1e6, lo_area, 1e-9 * lo_area) << i;
    EXPECT_NEAR(d.number(i, "kind1_area_mm2"), lo_area, 1e-9 * lo_area);
    EXPECT_EQ(d.number(i, "area_mm2"), d.number(i, "kind0_area_mm2"));  // the plain columns: kind 0's
  }
  EXPECT_NE(d.number(0, "kind1_top_width_mm"), d.number(1, "kind1_top_width_mm"));  // the angle changed it

  // A list: one file per kind (here both kinds to the high lifter's area).
  r = millwear_cmd("screen " + q(screen("list.toml", "['" + lab + "', '" + lab + "']")) + " -o " + q(dir / "list") +
                   " --emit parallel");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  d = io::read_csv((dir / "list/designs.csv").string());
  for (std::size_t i = 0; i < d.row_count(); ++i) EXPECT_NEAR(d.number(i, "kind1_area_mm2"), hi_area, 1e-9 * hi_area);

  // One file for a pattern, or a list of the wrong length: exit 2 naming screen.equal_area.
  for (const std::string& ea : {"'" + lab + "'", "['" + lab + "']"}) {
    r = millwear_cmd("screen " + q(screen("bad.toml", ea)) + " -o " + q(dir / "bad") + " --emit parallel");
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("screen.equal_area"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "bad"));
  }

  // A pattern candidate runs as a task: its summary has both kinds.
  r = millwear_cmd("screen-task " + q(dir / "base") + " 0");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const io::CsvData sum = io::read_csv((dir / "base/designs/d000/summary.csv").string());
  ASSERT_TRUE(sum.has_column("kind1_life_h"));
  // Ranked (d001 not run: exit 1) by the liner's life, the kind that gets there first, with
  // that kind's error, as `millwear run` gives it (from the kind's own rates' batch means).
  r = millwear_cmd("screen --collect " + q(dir / "base"));
  EXPECT_EQ(r.exit_code, 1) << r.output;
  const io::CsvData rank = io::read_csv((dir / "base/ranking.csv").string());
  ASSERT_EQ(rank.text(0, rank.column("design")), "d000");
  const double l0 = sum.number(0, "kind0_life_h"), l1 = sum.number(0, "kind1_life_h");
  EXPECT_EQ(rank.number(0, "life_h"), std::min(l0, l1));
  EXPECT_GT(rank.number(0, "life_sigma_h"), 0.0);
  EXPECT_EQ(rank.number(0, "life_sigma_h"), sum.number(0, "life_h_se"));
  EXPECT_EQ(sum.number(0, "life_h_se"), sum.number(0, l0 < l1 ? "kind0_life_h_se" : "kind1_life_h_se"));
  const std::string record = slurp(dir / "base/designs/d000/stages/d000_stage0.record");
  EXPECT_NE(record.find("kind.1.area_loss_rate_rel_sem"), std::string::npos);
}

// ---------------------------------------------------------------------------------------
// The screen module's pieces.

TEST(ScreenRanking, ParetoFrontKeepsOnlyUndominatedDesigns) {
  // life (more is better) against power (less is better).
  const std::vector<double> life{1000, 900, 800, 950};
  const std::vector<double> power{10, 8, 9, 12};
  const auto f = pareto_front(life, Better::Higher, power, Better::Lower);
  EXPECT_EQ(f, (std::vector<bool>{true, true, false, false}));  // 800@9 by 900@8; 950@12 by 1000@10
  EXPECT_EQ(pareto_front(life, Better::Higher, power, Better::Higher), (std::vector<bool>{true, false, false, true}));
  // Equal points do not dominate each other; a point with an unknown figure is off the front
  // and dominates nothing, however good its other figure.
  const std::vector<double> life2{1000, 1000, 2000, 500};
  const std::vector<double> power2{10, 10, NAN, 12};
  EXPECT_EQ(pareto_front(life2, Better::Higher, power2, Better::Lower), (std::vector<bool>{true, true, false, false}));
}

TEST(ScreenRanking, TiesWithinTwiceTheCombinedUncertainty) {
  std::vector<DesignResult> v(3);
  const double life[] = {1000, 900, 700}, sigma[] = {30, 40, 40};
  for (int i = 0; i < 3; ++i) {
    v[i].design.name = "d" + std::to_string(i);
    v[i].status = "finished";
    v[i].life_h = life[i];
    v[i].life_sigma_h = sigma[i];
    v[i].power_W = 1e3;
    v[i].utilization = 0.5;
  }
  v.push_back(DesignResult{});  // a missing design goes last, unranked
  v.back().design.name = "d3";
  v.insert(v.begin(), v[0]);  // a finished design that never wore: no life, unranked after the lives
  v.front().design.name = "unworn";
  v.front().life_h = std::nan("");
  const auto r = rank_designs(v, false);
  ASSERT_EQ(r.size(), 5u);
  EXPECT_EQ(r[0].rank, 1);
  EXPECT_EQ(r[2].rank, 3);
  EXPECT_TRUE(r[0].tied_with_best);
  EXPECT_TRUE(r[1].tied_with_best);    // 100 <= 2 * 50
  EXPECT_FALSE(r[2].tied_with_best);   // 300 > 100
  EXPECT_EQ(r[3].design.name, "unworn");
  EXPECT_EQ(r[3].status, "finished");
  EXPECT_EQ(r[3].rank, 0);
  EXPECT_NE(r[3].reason.find("no life"), std::string::npos);
  EXPECT_FALSE(r[3].tied_with_best);
  EXPECT_EQ(r[4].rank, 0);
  EXPECT_EQ(r[4].status, "missing");
}

TEST(ScreenRanking, TiesWithFewReplicatesTakeStudentsThreshold) {
  // 100 h apart with errors of 30 h each: 2.36 combined errors. One history each (batch means,
  // 2): apart. The same from two replicates each (Welch: 2 degrees of freedom, 4.5 combined
  // errors) or four (6, 2.5): tied. From sixteen (30, 2.1): apart.
  for (const auto& [replicates, tied] : std::vector<std::pair<int, bool>>{{1, false}, {2, true}, {4, true}, {16, false}}) {
    std::vector<DesignResult> v(2);
    for (int i = 0; i < 2; ++i) {
      v[i].design.name = "d" + std::to_string(i);
      v[i].status = "finished";
      v[i].life_h = 1000.0 - 100.0 * i;
      v[i].life_sigma_h = 30.0;
      v[i].replicates = replicates;
      v[i].error_source = replicates > 1 ? "replicates" : "batch_means";
    }
    const auto r = rank_designs(v, false);
    EXPECT_TRUE(r[0].tied_with_best);
    EXPECT_EQ(r[1].tied_with_best, tied) << replicates << " replicates";
  }
}

TEST(ScreenSampling, LatinHypercubeUsesEveryStratumOnceAndIsSeeded) {
  ScreenDef d;
  d.sampling = Sampling::LatinHypercube;
  d.samples = 10;
  d.seed = 7;
  d.height_mm.given = true;
  d.height_mm.is_range = true;
  d.height_mm.min = 10.0;
  d.height_mm.max = 20.0;
  d.leading_deg.given = true;
  d.leading_deg.values = {10.0, 20.0};  // a list: one level per half of the strata
  const Scene base = load_scene(src("scenarios/lab-mill.toml"));
  const auto c = sample_family(d, base);
  ASSERT_EQ(c.size(), 10u);
  std::vector<int> strata(10, 0);
  int low = 0;
  for (const auto& x : c) {
    ++strata[std::min(9, static_cast<int>((x.height_mm - 10.0)))];
    low += x.leading_deg == 10.0;
  }
  for (int n : strata) EXPECT_EQ(n, 1);
  EXPECT_EQ(low, 5);
  const auto again = sample_family(d, base);
  for (std::size_t i = 0; i < c.size(); ++i) EXPECT_EQ(c[i].height_mm, again[i].height_mm);
  d.seed = 8;
  EXPECT_NE(sample_family(d, base)[0].height_mm, c[0].height_mm);
}

TEST(ScreenSampling, GridTakesEveryCombinationLastParameterFastest) {
  ScreenDef d;
  d.rows.given = true;
  d.rows.values = {10, 12};
  d.directions = {"uni", "bi"};
  const Scene base = load_scene(src("scenarios/lab-mill.toml"));
  const auto c = sample_family(d, base);
  ASSERT_EQ(c.size(), 4u);
  EXPECT_EQ(c[0].rows, 10);
  EXPECT_EQ(c[0].direction, "uni");
  EXPECT_EQ(c[1].direction, "bi");
  EXPECT_EQ(c[2].rows, 12);
  EXPECT_EQ(c[0].height_mm, 20.0);  // the base scene's lifter where the family says nothing
}

TEST(ScreenJobs, SlurmArrayChunksTheDesigns) {
  EmitOptions o;
  o.binary = "/bin/millwear";
  o.out = "/x/out";
  o.name = "s";
  o.chunk = 2;
  o.max_running = 3;
  std::string tasks;
  const std::string s = slurm_script({0, 1, 2, 3, 5}, o, tasks);
  EXPECT_NE(s.find("#SBATCH --array=0-2%3\n"), std::string::npos) << s;
  EXPECT_EQ(tasks, "0 1\n2 3\n5\n");
  EXPECT_EQ(parallel_job_list({4}, o), "'/bin/millwear' screen-task '/x/out' 4\n");
}
