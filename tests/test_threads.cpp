// The soft engine's threaded step: the same bits for any thread count (more threads than
// cores included), on the lab mill and on a charge of about 10k disks.
#include <gtest/gtest.h>

#include <sched.h>
#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "../bench/probe_scene.hpp"
#include "cli_support.hpp"
#include "common/parallel.hpp"
#include "engine/engine.hpp"
#include "engine/soft/workers.hpp"
#include "engine_fixtures.hpp"
#include "study/charge_run.hpp"
#include "temp_dir.hpp"

using namespace millwear;

namespace {

// The loop over independent tasks runs every index once on any number of threads, and hands
// an exception of any type back to the caller (the lowest index's when several throw) after
// every thread has stopped, instead of ending the process.
TEST(ParallelTasks, EveryIndexOnceAndExceptionsComeBackToTheCaller) {
  for (int jobs : {1, 2, 3, 8}) {
    std::vector<std::atomic<int>> ran(37);
    for_each_index_parallel(ran.size(), jobs, [&](std::size_t i) { ran[i]++; });
    for (const auto& r : ran) EXPECT_EQ(r.load(), 1) << jobs << " jobs";
    try {
      for_each_index_parallel(37, jobs, [](std::size_t i) {
        if (i == 5 || i == 20) throw static_cast<int>(i);
      });
      ADD_FAILURE() << "nothing thrown with " << jobs << " jobs";
    } catch (int i) {
      // One job meets index 5 first and stops there; with more, 20 may be met first and
      // stop the handing out before 5: either way one of the thrown indices.
      if (jobs == 1) {
        EXPECT_EQ(i, 5);
      }
      EXPECT_TRUE(i == 5 || i == 20) << i;
    }
  }
  for_each_index_parallel(0, 4, [](std::size_t) { ADD_FAILURE() << "a task of none"; });
}

// Every position, spin and edge's shear work, and the energy sums, compared bit for bit.
void expect_same_bits(const ChargeState& s1, const Accounting& a1, const ChargeState& s2,
                      const Accounting& a2, int threads) {
  ASSERT_EQ(s1.size(), s2.size());
  for (std::size_t i = 0; i < s1.size(); ++i) {
    ASSERT_EQ(s1.active[i], s2.active[i]) << "disk " << i << ", threads " << threads;
    ASSERT_EQ(s1.position_m[i].x, s2.position_m[i].x) << "disk " << i << ", threads " << threads;
    ASSERT_EQ(s1.position_m[i].y, s2.position_m[i].y) << "disk " << i << ", threads " << threads;
    ASSERT_EQ(s1.spin_rad_s[i], s2.spin_rad_s[i]) << "disk " << i << ", threads " << threads;
  }
  ASSERT_EQ(a1.shear_work_J.size(), a2.shear_work_J.size());
  for (std::size_t e = 0; e < a1.shear_work_J.size(); ++e)
    ASSERT_EQ(a1.shear_work_J[e], a2.shear_work_J[e]) << "edge " << e << ", threads " << threads;
  EXPECT_EQ(a1.drive_work_J, a2.drive_work_J) << "threads " << threads;
  EXPECT_EQ(a1.pp_normal_J, a2.pp_normal_J) << "threads " << threads;
  EXPECT_EQ(a1.pp_tangent_J, a2.pp_tangent_J) << "threads " << threads;
  EXPECT_EQ(a1.solver_position_J, a2.solver_position_J) << "threads " << threads;
  EXPECT_EQ(a1.spectrum_energy_J, a2.spectrum_energy_J) << "threads " << threads;
}

}  // namespace

// The default counts of threads and jobs are the CPUs the process may run on: under
// `taskset` or a Slurm allocation of one CPU, one, not the machine's cores.
TEST(ParallelTasks, TheCoresCountedAreThoseTheProcessMayRunOn) {
  cpu_set_t all;
  ASSERT_EQ(sched_getaffinity(0, sizeof all, &all), 0);
  int first = 0;
  while (!CPU_ISSET(first, &all)) ++first;
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(first, &one);
  ASSERT_EQ(sched_setaffinity(0, sizeof one, &one), 0);
  const int cores = core_count(), jobs = jobs_for(0, 8), threads = step_threads_beside(0, 1);
  ASSERT_EQ(sched_setaffinity(0, sizeof all, &all), 0);
  EXPECT_EQ(cores, 1);
  EXPECT_EQ(jobs, 1);
  EXPECT_EQ(threads, 1);
  EXPECT_EQ(core_count(), CPU_COUNT(&all));
}

// A thread the system cannot start (here an address-space limit a few thread stacks above
// what the process has mapped) is left out: start_threads returns those it started, and the
// parallel loop does every index on them and the caller.
TEST(ParallelTasks, ThreadsTheSystemCannotStartAreLeftOut) {
  long mapped_kb = 0;
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmSize:", 0) == 0) mapped_kb = std::stol(line.substr(7));
  ASSERT_GT(mapped_kb, 0);
  rlimit old{};
  ASSERT_EQ(getrlimit(RLIMIT_AS, &old), 0);
  rlimit tight = old;
  tight.rlim_cur = static_cast<rlim_t>(mapped_kb + 48 * 1024) * 1024;
  if (old.rlim_cur != RLIM_INFINITY) tight.rlim_cur = std::min(tight.rlim_cur, old.rlim_cur);
  std::atomic<bool> go{false};
  std::atomic<int> ran{0};
  std::vector<int> done(4000, 0);
  ASSERT_EQ(setrlimit(RLIMIT_AS, &tight), 0);
  std::vector<std::thread> started = start_threads(256, [&](int) {
    while (!go.load()) std::this_thread::yield();
    ++ran;
  });
  for_each_index_parallel(done.size(), 256, [&](std::size_t i) { ++done[i]; });
  EXPECT_EQ(setrlimit(RLIMIT_AS, &old), 0);
  go = true;
  for (std::thread& t : started) t.join();
  EXPECT_LT(started.size(), 256u);
  EXPECT_EQ(ran.load(), static_cast<int>(started.size()));
  for (std::size_t i = 0; i < done.size(); ++i) ASSERT_EQ(done[i], 1) << i;
}

// Where the system cannot start every thread asked for (here an address-space limit that
// leaves room for a few thread stacks), the step runs on those it started, with the same
// results; a thread that failed to start aborted the program (exit 134).
TEST(SoftThreads, ThreadsTheSystemCannotStartLeaveTheSameResults) {
  namespace fs = std::filesystem;
  const millwear::testing::TempDir dir("millwear-threads-limit");
  const std::string scene = millwear::testing::source_path("scenarios/lab-mill.toml");
  const std::string args = " --revolutions 0.01 --set solver.settle_time=0.01 --set solver.spinup_revolutions=0.01 -q";
  // Without gnuplot on the PATH (the results stand alone): the limit would hold it too.
  const std::string bin = "PATH=/nonexistent \"" + std::string(MILLWEAR_BINARY) + "\" charge \"" + scene + "\" -o ";
  const auto one = millwear::testing::run_shell(bin + "\"" + (dir / "one").string() + "\" --threads 1" + args);
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const auto many =
      millwear::testing::run_shell("ulimit -v 300000; " + bin + "\"" + (dir / "many").string() + "\" --threads 256" + args);
  ASSERT_EQ(many.exit_code, 0) << many.output;
  for (const char* f : {"snapshot_lab-mill.csv", "liner_work.csv", "spectrum.csv", "impacts.csv"}) {
    const std::string a = millwear::testing::read_text(dir / "one" / f);
    EXPECT_FALSE(a.empty()) << f;
    EXPECT_EQ(a, millwear::testing::read_text(dir / "many" / f)) << f;
  }
}

TEST(SoftThreads, ThreadCountDoesNotChangeTheBitsOnTheLabMill) {
  Scene scene = millwear::testing::lab_mill();
  scene.solver.backend = Backend::Soft;
  scene.run.revolutions = 0.5;
  scene.solver.spinup_revolutions = 0.2;
  scene.solver.threads = 1;
  const ChargeRunResult one = run_charge_only(scene);
  EXPECT_GT(one.accounting.drive_work_J, 0.0);
  for (int threads = 2; threads <= 4; ++threads) {
    scene.solver.threads = threads;
    const ChargeRunResult many = run_charge_only(scene);
    expect_same_bits(one.final_state, one.accounting, many.final_state, many.accounting, threads);
  }
}

// About 10k disks of 9-15 mm in the 5 m probe mill: a bed settled for 0.2 s, then the mill
// turned for 70 steps (two reorderings of the disks, at steps 0 and 64 of the window), with
// the collision spectrum on so that its ordered sums are compared too.
TEST(SoftThreads, ThreadCountDoesNotChangeTheBitsOnTenThousandDisks) {
  Scene scene = bench::probe_scene(0.0091);
  scene.solver.backend = Backend::Soft;
  scene.solver.substeps = 4;
  scene.charge.species[0].rolling_resistance = 0.05;
  scene.outputs.collision_spectrum = true;
  const MillGeometry mill = build_scene_mill(scene);
  ChargeState bed;
  {
    scene.solver.threads = 2;
    auto engine = make_engine(scene, mill, fill_charge(scene, mill), accounting_options_for(scene));
    engine->set_mill_speed(0.0);
    engine->step(120);
    bed = engine->state();
  }
  ASSERT_GT(bed.size(), 9000u);
  auto run = [&](int threads, ChargeState& state, Accounting& acc) {
    scene.solver.threads = threads;
    auto engine = make_engine(scene, mill, bed, accounting_options_for(scene));
    engine->set_mill_speed(scene.angular_speed_rad_s());
    engine->reset_window();
    engine->step(70);
    state = engine->state();
    acc = engine->accounting();
  };
  ChargeState s1;
  Accounting a1;
  run(1, s1, a1);
  EXPECT_GT(a1.pp_normal_J, 0.0);
  EXPECT_GT(a1.drive_work_J, 0.0);
  for (int threads = 2; threads <= 4; ++threads) {
    ChargeState s;
    Accounting a;
    run(threads, s, a);
    expect_same_bits(s1, a1, s, a, threads);
  }
}

// The pool runs every range of a stage exactly once, whatever the thread count, the number
// of ranges and how the blocks are cut (equal blocks, blocks cut by disk, a thread whose
// block is empty so that it only steals), stage after stage.
TEST(SoftThreads, ThePoolRunsEveryRangeOnce) {
  for (int threads = 1; threads <= 4; ++threads) {
    soft::Workers workers(threads);
    for (int ranges : {0, 1, 2, 3, 7, 64, 1000}) {
      std::vector<std::atomic<int>> runs(static_cast<std::size_t>(ranges));
      for (auto& r : runs) r.store(0);
      constexpr int kStages = 300;
      for (int stage = 0; stage < kStages; ++stage) {
        const auto count = [&](int r) { runs[static_cast<std::size_t>(r)].fetch_add(1); };
        if (stage % 3 == 0) {
          workers.run(ranges, count);
        } else if (stage % 3 == 1) {
          // Ranges spread evenly over disks [0, 10 ranges).
          workers.run_by_disk(ranges, 10 * ranges, [](int r) { return 10 * r; }, count);
        } else {
          // Every range at disk 0: every thread but the first has an empty block.
          workers.run_by_disk(ranges, 10 * ranges, [](int) { return 0; }, count);
        }
      }
      for (int r = 0; r < ranges; ++r)
        ASSERT_EQ(runs[static_cast<std::size_t>(r)].load(), kStages)
            << "range " << r << " of " << ranges << ", threads " << threads;
    }
  }
}

// The solver keeps the disks in cell order and reorders them every 64 steps; what it hands
// out is by the caller's ids. Turning through two reorderings one step at a time, every disk
// moves less than its radius per step (a disk handed out under another's id would jump by
// the spacing of the cell order, a diameter or more).
TEST(SoftThreads, TheStateFollowsEachDiskThroughTheReorderings) {
  Scene scene = bench::probe_scene(0.0287);
  scene.solver.backend = Backend::Soft;
  scene.solver.threads = 2;
  const MillGeometry mill = build_scene_mill(scene);
  auto engine = make_engine(scene, mill, fill_charge(scene, mill), accounting_options_for(scene));
  engine->set_mill_speed(0.0);
  engine->step(120);
  engine->set_mill_speed(scene.angular_speed_rad_s());
  ChargeState before = engine->state();
  double fastest_m = 0.0;
  for (int step = 0; step < 140; ++step) {
    engine->step(1);
    const ChargeState& after = engine->state();
    for (std::size_t i = 0; i < after.size(); ++i) {
      if (!after.active[i]) continue;
      const double dx = after.position_m[i].x - before.position_m[i].x;
      const double dy = after.position_m[i].y - before.position_m[i].y;
      const double moved_m = std::sqrt(dx * dx + dy * dy);
      fastest_m = std::max(fastest_m, moved_m);
      ASSERT_LT(moved_m, after.radius_m[i]) << "disk " << i << ", step " << step;
    }
    before = after;
  }
  EXPECT_GT(fastest_m, 0.0);
}

// Without --threads the step takes one thread per kDisksPerStepThread disks, up to the count
// it was given; a count given on the command line is used as it is.
TEST(SoftThreads, ACountFittedToTheSizeTakesAThreadPerBlockOfDisks) {
  SolverDef s;
  s.threads = 2;
  s.threads_fit_size = true;
  EXPECT_EQ(step_thread_count(s, 217), 1);
  EXPECT_EQ(step_thread_count(s, kDisksPerStepThread - 1), 1);
  EXPECT_EQ(step_thread_count(s, 2 * kDisksPerStepThread), 2);
  EXPECT_EQ(step_thread_count(s, 100 * kDisksPerStepThread), 2);  // never more than given
  s.threads_fit_size = false;
  EXPECT_EQ(step_thread_count(s, 217), 2);
  s.threads = 0;
  EXPECT_EQ(step_thread_count(s, 217), 1);
}
