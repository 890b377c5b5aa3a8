// The screen's local worker pool and its tasks (screen/pool.hpp, screen/task.hpp,
// screen/run_screen.hpp, screen/collect.hpp) on their own, with a stand-in for
// `millwear screen-task`: a shell script whose exit depends on the task number. The real
// screen end to end is tests/test_screen.cpp.
#include <gtest/gtest.h>

#include <sys/stat.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "common/errors.hpp"
#include "engine_fixtures.hpp"
#include "io/run_folder.hpp"
#include "screen/collect.hpp"
#include "screen/pool.hpp"
#include "screen/run_screen.hpp"
#include "screen/task.hpp"
#include "temp_dir.hpp"

namespace millwear::screen {
namespace {

namespace fs = std::filesystem;


std::vector<Candidate> three_designs(const fs::path& out) {
  std::vector<Candidate> v(3);
  for (int i = 0; i < 3; ++i) {
    v[i].name = "d00" + std::to_string(i);
    fs::create_directories(design_dir(out.string(), v[i].name));
  }
  return v;
}

// `EXE screen-task OUT I`: task 0 finishes, task 1 fails, task 2 dies of SIGKILL.
std::string fake_task(const fs::path& dir) {
  const fs::path exe = dir / "fake-task.sh";
  std::ofstream(exe) << "#!/bin/sh\necho \"task $3 of $2\"\ncase $3 in 0) exit 0;; 1) exit 1;; *) kill -9 $$;; esac\n";
  fs::permissions(exe, fs::perms::owner_all);
  return exe.string();
}

TEST(ScreenPool, EachTaskRunsInItsOwnProcessAndACrashIsAFailedStatus) {
  const testing::TempDir dir("millwear-screen-pool-crash");
  const fs::path out = dir.path();
  const std::vector<Candidate> designs = three_designs(out);
  PoolOptions o;
  o.exe = fake_task(out);
  o.jobs = 8;
  int jobs_started = 0;
  PoolProgress last;
  o.on_start = [&](int jobs) { jobs_started = jobs; };
  o.on_tick = [&](const PoolProgress& p) { last = p; };
  const PoolOutcome r = run_task_pool(out.string(), designs, {0, 1, 2}, 0, o);
  EXPECT_EQ(r.signal, 0);
  EXPECT_EQ(r.jobs, 3);  // never more jobs than tasks
  EXPECT_EQ(jobs_started, 3);
  // The last tick comes after every task ended: its counts are final.
  EXPECT_EQ(last.total, 3);
  EXPECT_EQ(last.done, 1);
  EXPECT_EQ(last.failed, 2);
  EXPECT_EQ(last.running, 0);
  EXPECT_FALSE(std::isnan(last.left_s));
  // Each task's output went to its log.
  EXPECT_EQ(testing::read_text(out / "logs/d001.log"), "task 1 of " + out.string() + "\n");
  // Only the task that died without a word gets a status from the pool.
  EXPECT_FALSE(fs::exists(task_status_path(out.string(), "d000")));
  EXPECT_FALSE(fs::exists(task_status_path(out.string(), "d001")));
  const io::KeyValues kv = io::read_key_values(task_status_path(out.string(), "d002"));
  EXPECT_EQ(io::find_value(kv, "status"), "failed");
  EXPECT_EQ(io::find_value(kv, "exit_code"), "137");
  EXPECT_NE(io::find_value(kv, "reason").find("signal 9"), std::string::npos);
}

TEST(ScreenPool, AStopSignalStartsNoTask) {
  const testing::TempDir dir("millwear-screen-pool-stop");
  const fs::path out = dir.path();
  const std::vector<Candidate> designs = three_designs(out);
  const std::atomic<int> stop{15};
  PoolOptions o;
  o.exe = fake_task(out);
  o.jobs = 1;
  o.stop_signal = &stop;
  PoolProgress last;
  o.on_tick = [&](const PoolProgress& p) { last = p; };
  const PoolOutcome r = run_task_pool(out.string(), designs, {0, 1, 2}, 1, o);
  EXPECT_EQ(r.signal, 15);
  EXPECT_EQ(last.done, 1);  // the design finished before, nothing more
  EXPECT_EQ(last.failed, 0);
  EXPECT_TRUE(std::isnan(last.left_s));  // nothing finished in this pool: no rate to go by
  EXPECT_FALSE(fs::exists(out / "logs/d000.log"));
}

TEST(ScreenTask, StatusRoundTripsWithLineEndsInTheReasonAsSpaces) {
  const testing::TempDir dir("millwear-screen-pool-status");
  const fs::path out = dir.path();
  const std::vector<Candidate> designs = three_designs(out);
  write_task_status(out.string(), designs[0], "failed", 1, "first line\nsecond\rthird");
  const io::KeyValues kv = io::read_key_values(task_status_path(out.string(), "d000"));
  EXPECT_EQ(io::find_value(kv, "reason"), "first line second third");
  EXPECT_FALSE(design_finished(out.string(), designs[0]));
  write_task_status(out.string(), designs[0], "finished", 0, "");
  EXPECT_TRUE(design_finished(out.string(), designs[0]));
  EXPECT_FALSE(design_finished(out.string(), designs[1]));  // no status at all
}

TEST(ScreenTask, ATaskNumberOutsideTheDesignsIsAnInputError) {
  const testing::TempDir dir("millwear-screen-pool-range");
  const fs::path out = dir.path();
  const std::vector<Candidate> designs = three_designs(out);
  try {
    run_screen_task(out.string(), designs, 3);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "I");
    EXPECT_NE(std::string(e.what()).find("[0, 2]"), std::string::npos) << e.what();
  }
}

// A designs.csv of no row is a damaged list (a screen writes every valid candidate), named
// as such: no range of task numbers is made of it.
TEST(ScreenTask, AListOfNoDesignIsRefusedAsDamagedNotAsARangeOfTasks) {
  const testing::TempDir dir("millwear-screen-pool-empty");
  const fs::path out = dir.path();
  std::ofstream(out / "designs.csv") << "task,design,sample,height_mm,top_width_mm,leading_face_angle_deg,"
                                        "trailing_face_angle_deg,rows,direction,area_mm2,profile_source,scene_file,"
                                        "profile_file\n";
  for (int pass = 0; pass < 2; ++pass) {
    try {
      if (pass == 0) run_screen_tasks(out.string(), {0}, {}, nullptr);
      else run_screen_task(out.string(), {}, 0);
      FAIL() << "expected InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file, designs_csv(out.string()));
      EXPECT_EQ(e.where, "line 2") << e.what();
      EXPECT_NE(std::string(e.what()).find("at least one design"), std::string::npos) << e.what();
    }
  }
  EXPECT_FALSE(fs::exists(out / "designs")) << "a task ran";
}

// The histories a task runs come from screen.key; a count the screen would not write there is
// refused naming the file and key before the task starts (no status, nothing run), not read
// as a number's prefix or failed as the design's error.
TEST(ScreenTask, ADamagedReplicatesCountInTheScreenKeyIsRefusedBeforeTheTaskStarts) {
  const testing::TempDir dir("millwear-screen-pool-key");
  const fs::path out = dir.path();
  const std::vector<Candidate> designs = three_designs(out);
  for (const char* bad : {"abc", "", "2x", "99999999999", "0", "1001"}) {
    std::ofstream(screen_key_path(out.string())) << "# millwear screen\nreplicates=" << bad << "\n";
    try {
      run_screen_task(out.string(), designs, 0);
      ADD_FAILURE() << "'" << bad << "': expected InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(e.file, screen_key_path(out.string())) << e.what();
      EXPECT_EQ(e.where, "replicates") << e.what();
    }
    EXPECT_FALSE(fs::exists(task_status_path(out.string(), "d000"))) << "'" << bad << "': the task started";
    fs::remove(task_status_path(out.string(), "d000"));
  }
}

TEST(ScreenCollect, AFolderWithoutAScreenIsAnInputError) {
  const testing::TempDir dir("millwear-screen-pool-nothing");
  const fs::path out = dir.path();
  EXPECT_THROW(collect_screen(out.string()), InputError);
}

TEST(ScreenRequest, AnUnknownEmitTargetIsAnInputErrorBeforeAnythingIsWritten) {
  const testing::TempDir dir("millwear-screen-pool-emit");
  const fs::path out = dir / "out";
  ScreenRequest r;
  r.screen_file = testing::source_path("tests/data/screen-lab.toml");
  r.out = out.string();
  r.emit = "pbs";
  try {
    read_screen_inputs(r);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where, "--emit");
  }
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace millwear::screen
