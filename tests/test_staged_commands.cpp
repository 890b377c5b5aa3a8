// `charge`, `sweep`, `rule1 -o` and `tradeoff` run again into their own folder, as a user
// runs them (the built binary): a run that fails or is stopped leaves the earlier results byte
// for byte, and a run that ends replaces them and removes the earlier files it does not
// write again (io/staging.hpp). The runs are the lab mill's at draft fidelity, a fraction of a
// revolution or one short stage; a stopped run is told to settle for 1000 simulated seconds
// (minutes of computing) and signalled once it has begun its work.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <map>
#include <string>

#include "cli_support.hpp"
#include "io/staging.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;

namespace millwear {
namespace {

using millwear::testing::TempDir;
constexpr auto run = &millwear::testing::run_millwear;
constexpr auto q = &millwear::testing::quoted;

std::string lab() { return q(fs::path(MILLWEAR_SOURCE_DIR) / "scenarios/lab-mill.toml"); }

// Every file under OUT but those a killed command leaves of its own: its staging folder
// (cleared by the next command into OUT) and its lock file (which holds no lock once the
// process is gone).
std::map<std::string, std::string> results_in(const fs::path& out) {
  std::map<std::string, std::string> files = millwear::testing::files_under(out);
  for (auto it = files.begin(); it != files.end();) {
    const bool own = it->first.rfind(std::string(io::kStagingName) + "/", 0) == 0 || it->first == ".millwear.lock";
    it = own ? files.erase(it) : std::next(it);
  }
  return files;
}

// `millwear ARGS` (told to settle its charge for 1000 simulated seconds) sent SIGTERM once it
// has begun its work in OUT: it holds OUT's lock and has drawn up its staging folder or
// deleted the earlier manifest. Returns the log; `status` gets the wait status.
std::string stop_at_work(const TempDir& dir, const std::string& args, const fs::path& out, int& status) {
  const fs::path log = dir / "stopped.log";
  const pid_t pid = millwear::testing::spawn_millwear(args + " --set solver.settle_time=1000", log);
  EXPECT_GT(pid, 0);
  if (pid <= 0) return "";
  const std::string holder = "pid=" + std::to_string(pid);
  const auto r = millwear::testing::stop_when(
      pid,
      [&] {
        return millwear::testing::read_text(out / ".millwear.lock").find(holder) != std::string::npos &&
               (fs::exists(out / io::kStagingName) || !fs::exists(out / "manifest.json"));
      },
      SIGTERM);
  status = r.status;
  EXPECT_TRUE(r.sent);
  EXPECT_TRUE(r.stopped_in_time);
  return millwear::testing::read_text(log);
}

// The folder after a run that ended: nothing of its staging left.
void expect_no_staging(const fs::path& out) { EXPECT_FALSE(fs::exists(out / io::kStagingName)); }

// A charge with its contact log, then one stopped while settling: the first's files stay as
// they were. A charge that ends without the log replaces them and removes contacts.csv.
TEST(StagedCommands, AStoppedChargeLeavesTheEarlierChargeAndOneThatEndsReplacesIt) {
  const TempDir dir("millwear-staged-charge");
  const fs::path out = dir / "out";
  const std::string base = "charge " + lab() + " -o " + q(out) + " --fidelity draft --revolutions 0.5 -q";
  auto r = run(base + " --set outputs.contact_log=true");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(out / "contacts.csv"));
  const auto before = results_in(out);

  int status = 0;
  const std::string log = stop_at_work(dir, base, out, status);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << log;
  EXPECT_NE(log.find("millwear charge: interrupted; nothing of this charge is kept"), std::string::npos) << log;
  EXPECT_EQ(millwear::testing::changed_files(before, results_in(out)), "");

  r = run(base + " --set solver.seed=2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto after = millwear::testing::files_under(out);
  EXPECT_FALSE(fs::exists(out / "contacts.csv")) << "the earlier charge's contact log";
  EXPECT_NE(after.at("charge_summary.csv"), before.at("charge_summary.csv"));
  EXPECT_EQ(after.at("manifest.json").find("contacts.csv"), std::string::npos);
  EXPECT_NE(after.at("manifest.json").find("\"solver.seed=2\""), std::string::npos);
  expect_no_staging(out);
}

// A sweep of two values, then one stopped (SIGTERM) in its first point: the first sweep's
// files stay as they were. A sweep of one value that ends replaces them and removes the
// earlier second point.
TEST(StagedCommands, AStoppedSweepLeavesTheEarlierSweepAndOneThatEndsReplacesIt) {
  const TempDir dir("millwear-staged-sweep");
  const fs::path out = dir / "out";
  const std::string base = "sweep " + lab() + " -o " + q(out) + " --fidelity draft --revolutions 0.5 --no-plot -q -j 1";
  auto r = run(base + " --vary mill.speed=0.6,0.7");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(out / "points/01/charge_summary.csv"));
  const auto before = results_in(out);

  int status = 0;
  const std::string log = stop_at_work(dir, base + " --vary mill.speed=0.6,0.8", out, status);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << log;
  EXPECT_EQ(millwear::testing::changed_files(before, results_in(out)), "");

  r = run(base + " --vary mill.speed=0.65");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(out / "points/01")) << "the earlier sweep's second point";
  const std::string table = millwear::testing::read_text(out / "sweep.csv");
  EXPECT_NE(table.find("mill.speed,0.65,"), std::string::npos) << table;
  EXPECT_EQ(table.find("mill.speed,0.7,"), std::string::npos) << table;
  expect_no_staging(out);
}

// rule 1 into a folder, then a check stopped (SIGTERM) in its histories: the first check's
// files stay as they were. A check that ends without gnuplot replaces them and removes the
// earlier figure.
TEST(StagedCommands, AStoppedRuleOneCheckLeavesTheEarlierCheckAndOneThatEndsReplacesIt) {
  const TempDir dir("millwear-staged-rule1");
  const fs::path out = dir / "out";
  const std::string base =
      "rule1 " + lab() + " -o " + q(out) + " --fidelity draft --factors 1e5 2e5 --replicates 1 -j 2";
  auto r = run(base);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(out / "plots/fig5_rule1.png"));
  const auto before = results_in(out);

  int status = 0;
  const std::string log = stop_at_work(dir, base, out, status);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << log;
  EXPECT_EQ(millwear::testing::changed_files(before, results_in(out)), "");

  r = millwear::testing::run_shell("env PATH=" + q(dir.path()) + " \"" + MILLWEAR_BINARY + "\" " + base +
                                   " --set solver.seed=2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* f : {"plots/fig5_rule1.png", "plots/fig5_rule1.svg"})
    EXPECT_FALSE(fs::exists(out / f)) << "the earlier check's " << f;
  const std::string manifest = millwear::testing::read_text(out / "manifest.json");
  EXPECT_NE(manifest.find("\"solver.seed=2\""), std::string::npos) << manifest;
  EXPECT_NE(millwear::testing::read_text(out / "rule1.csv"), before.at("rule1.csv"));
  expect_no_staging(out);
}

// A ladder of two settings (the reference and draft, with its figure), then one whose
// reference fails (rule 1's bound on wear.factor stops its history at the first update): exit
// 1 and the first ladder's files as they were. A ladder of the reference alone (no figure)
// replaces them and removes the earlier figure.
TEST(StagedCommands, AFailedTradeoffLeavesTheEarlierLadderAndOneThatEndsReplacesIt) {
  const TempDir dir("millwear-staged-tradeoff");
  const fs::path out = dir / "out";
  const std::string base = "tradeoff " + lab() + " -o " + q(out) + " --stages 1 --stage-hours 1";
  auto r = run(base + " --only draft");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(fs::exists(out / "tradeoff.svg"));
  const auto before = results_in(out);

  r = run("tradeoff " + lab() + " -o " + q(out) +
          " --quick --stages 1 --no-plot --set wear.mode=continuous --set wear.factor=3e6");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("the reference run failed"), std::string::npos) << r.output;
  EXPECT_EQ(millwear::testing::changed_files(before, millwear::testing::files_under(out)), "");

  r = run(base + " --only reference");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* f : {"tradeoff.png", "tradeoff.svg", "gnuplot.log"})
    EXPECT_FALSE(fs::exists(out / f)) << "the earlier ladder's " << f;
  EXPECT_NE(millwear::testing::read_text(out / "tradeoff.csv"), before.at("tradeoff.csv"));
  expect_no_staging(out);
}

}  // namespace
}  // namespace millwear
