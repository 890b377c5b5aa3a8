// `millwear screen SCREEN -o OUT`: a family of lifter designs run and ranked by life.
// `millwear screen-task OUT I [I...]`: one design (row I of OUT/designs.csv) run through
// `millwear run`'s own code path into OUT/designs/NAME.
//
//   millwear screen SCREEN -o OUT [--jobs N] [--resume]      local worker pool, then ranking
//   millwear screen SCREEN -o OUT --emit parallel|slurm [--chunk K] [--jobs M]
//                                                             job list / sbatch array script
//   millwear screen --collect OUT                             ranking of whatever finished
//
// The local pool starts one `millwear screen-task` process per design (the same command GNU
// parallel and Slurm run), so a crash of one design never takes the others down and every
// way of running gives the same files. Each design is deterministic (its scene and seed) and
// writes only into its own folder: ranking.csv does not depend on N or on how it was run.
//
// Exit codes: 0 every design finished and was ranked; 1 a design failed or is missing (the
// ranking lists it); 2 bad input (screen file, base scene, no valid candidate); 130/143
// interrupted (--resume continues).
#include <CLI/CLI.hpp>

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <thread>

#include "app/commands.hpp"
#include "app/duration_text.hpp"
#include "app/output_folder.hpp"
#include "app/signals.hpp"
#include "io/hash.hpp"
#include "millwear_commit.hpp"  // generated at build time: MILLWEAR_COMMIT
#include "study/plan.hpp"
#include "study/run_designs.hpp"
#include "common/errors.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/folder_lock.hpp"
#include "io/run_folder.hpp"
#include "plots/plots.hpp"
#include "scene/scene.hpp"
#include "screen/jobs.hpp"
#include "screen/ranking.hpp"
#include "screen/screen.hpp"

extern char** environ;

namespace millwear::app {

namespace fs = std::filesystem;
using namespace millwear::screen;

namespace {

struct ScreenArgs {
  std::string screen;  // screen file (or OUT with --collect)
  std::string out;
  int jobs = 0;
  bool resume = false;
  bool collect = false;
  bool quiet = false;
  std::string emit;
  int chunk = 1;
};

std::string key_path(const std::string& out) { return io::join_path(out, "screen.key"); }

std::string abs_path(const std::string& p) { return fs::absolute(p).lexically_normal().string(); }

std::string self_exe() {
  std::error_code ec;
  const fs::path p = fs::read_symlink("/proc/self/exe", ec);
  return ec ? std::string("millwear") : p.string();
}

bool design_finished(const std::string& out, const Candidate& c) {
  if (!io::file_exists(task_status_path(out, c.name))) return false;
  try {
    return io::find_value(io::read_key_values(task_status_path(out, c.name)), "status") == "finished";
  } catch (const std::exception&) {
    return false;
  }
}

void write_task_status(const std::string& out, const Candidate& c, const std::string& status,
                       int exit_code, const std::string& reason) {
  io::KeyValues kv{{"design", c.name}, {"status", status}, {"exit_code", std::to_string(exit_code)}};
  std::string r = reason;
  std::replace(r.begin(), r.end(), '\n', ' ');
  std::replace(r.begin(), r.end(), '\r', ' ');
  if (!r.empty()) kv.emplace_back("reason", r);
  io::write_file_atomic(task_status_path(out, c.name), io::format_key_values(kv, "millwear screen-task"));
}

// ---------------------------------------------------------------------------------------
// screen-task: one design through `millwear run`'s code path.

int run_one_task(const std::string& out, const std::vector<Candidate>& designs, int index) {
  if (index < 0 || index >= static_cast<int>(designs.size()))
    throw InputError(designs_csv(out), "I",
                     "a task number in [0, " + std::to_string(designs.size() - 1) + "], got " + std::to_string(index));
  const Candidate& c = designs[static_cast<std::size_t>(index)];
  const std::string dir = design_dir(out, c.name);
  const io::FolderLock lock(dir);  // before the status: a task refused here changes nothing
  write_task_status(out, c, "running", -1, "");
  int rc = 1;
  std::string reason;
  try {
    // The same code path as `millwear run`: the candidate's folder is what run writes. A
    // re-run task (Slurm requeue, re-emitted job) continues its stages.
    const study::Plan plan = study::make_plan({{io::join_path(out, c.scene_file)}, "", "", dir});
    study::RunState state(plan);
    SignalScope signals;
    study::RunOptions opt;
    opt.out = dir;
    opt.resume = true;
    opt.lock_folder = false;  // held above
    opt.jobs = 1;
    opt.stop_signal = &g_signal;
    opt.commit = MILLWEAR_COMMIT;
    const study::RunOutcome r = study::run_designs(state, opt);
    rc = r.interrupted ? 128 + (r.signal == SIGTERM ? SIGTERM : SIGINT) : r.failed || r.figures_failed ? 1 : 0;
    if (rc == 1) {
      reason = state.designs[0]->error;
      if (reason.empty()) reason = "figures failed (see plots/gnuplot.log in the design's folder): " + r.figure_error;
    }
    // The task's log (logs/NAME.log under GNU parallel and Slurm) says how it ended.
    const study::DesignState& st = *state.designs[0];
    std::printf("%s: %s after %.1f s%s%s\n", c.name.c_str(), study::status_name(st.status), r.wall_s,
                st.error.empty() ? "" : ": ", st.error.c_str());
    for (const auto& e : st.events) std::printf("%s: event: %s\n", c.name.c_str(), e.c_str());
    if (!r.figure_error.empty()) std::fprintf(stderr, "millwear: warning: figures: %s\n", r.figure_error.c_str());
  } catch (const std::exception& e) {
    rc = dynamic_cast<const InputError*>(&e) ? 2 : 1;
    reason = e.what();
    std::fprintf(stderr, "millwear: %s: %s\n", rc == 2 ? "error" : "run failed", reason.c_str());
  }
  if (rc == 0) write_task_status(out, c, "finished", 0, "");
  else if (rc == 1 || rc == 2) write_task_status(out, c, "failed", rc, reason);
  else write_task_status(out, c, "interrupted", rc, "interrupted (exit " + std::to_string(rc) + "); run it again to continue");
  return rc;
}

int screen_task_command(const std::string& out, const std::vector<int>& indices) {
  const std::vector<Candidate> designs = read_designs(out);
  int worst = 0;
  for (int i : indices) {
    const int rc = run_one_task(out, designs, i);
    if (rc > 1) return rc;  // interrupted: stop here
    worst = std::max(worst, rc);
  }
  return worst;
}

// ---------------------------------------------------------------------------------------
// Ranking, figures, report

std::vector<std::string> split_words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> w;
  for (std::string x; in >> x;) w.push_back(x);
  return w;
}

double param_value(const Candidate& c, const std::string& name) {
  if (name == "height_mm") return c.height_mm;
  if (name == "top_width_mm") return c.top_width_mm;
  if (name == "leading_face_angle_deg") return c.leading_deg;
  if (name == "trailing_face_angle_deg") return c.trailing_deg;
  if (name == "rows") return c.rows;
  return std::nan("");
}

// Figures of the ranking. Returns the failures as text ("" when all drawn).
std::string render_screen_figures(const std::string& out, const std::vector<DesignResult>& ranked,
                                  const io::KeyValues& key) {
  if (!plots::gnuplot_available()) return "gnuplot not installed: figures skipped";
  const std::string plots_dir = io::join_path(out, "plots"), data_dir = io::join_path(plots_dir, "data");
  io::ensure_dir(data_dir);
  const std::string log = io::join_path(plots_dir, "gnuplot.log");
  std::string failures;
  auto draw = [&](const std::string& fig, std::map<std::string, std::string> vars) {
    vars["datadir"] = out;
    vars["outbase"] = io::join_path(plots_dir, fig);
    try {
      plots::render_figure(plots::script_path(fig), vars, log);
    } catch (const std::exception& e) {
      failures += (failures.empty() ? "" : "; ") + fig + ": " + e.what();
    }
  };
  std::vector<const DesignResult*> done;
  for (const auto& r : ranked)
    if (r.status == "finished" && std::isfinite(r.life_h)) done.push_back(&r);
  if (done.empty()) return "no finished design: figures skipped";
  draw("screen_pareto", {{"power_sense", io::find_value(key, "power", "min")}});

  // The top three: new and last-stage profiles from each design's run folder.
  std::string blocks, names;
  for (std::size_t i = 0; i < done.size() && i < 3; ++i) {
    const std::string dir = design_dir(out, done[i]->design.name);
    const std::vector<int> st = io::list_finished_stages(dir, done[i]->design.name);
    if (st.empty()) continue;
    for (int k : {0, st.back()}) {
      const io::CsvData p = io::read_csv(io::profile_path(dir, done[i]->design.name, k));
      for (std::size_t r = 0; r < p.row_count(); ++r)
        blocks += io::format_number(p.number(r, "x_mm")) + "," + io::format_number(p.number(r, "y_mm")) + "\n";
      blocks += "\n\n";
    }
    names += (names.empty() ? "" : " ") + done[i]->design.name;
  }
  io::write_file_atomic(io::join_path(data_dir, "top_profiles.dat"), blocks);
  draw("screen_top_profiles", {{"designs", names}});

  // Heat map for a family with exactly two numeric parameters.
  const std::vector<std::string> varying = split_words(io::find_value(key, "varying"));
  if (varying.size() == 2 && std::isfinite(param_value(Candidate{}, varying[0])) &&
      std::isfinite(param_value(Candidate{}, varying[1]))) {
    std::string rows;
    for (const DesignResult* r : done)
      rows += io::format_number(param_value(r->design, varying[0])) + "," +
              io::format_number(param_value(r->design, varying[1])) + "," + io::format_number(r->life_h) + "," +
              r->design.name + "\n";
    io::write_file_atomic(io::join_path(data_dir, "heatmap.dat"), rows);
    draw("screen_heatmap", {{"xlabel_text", varying[0]}, {"ylabel_text", varying[1]}});
  }
  return failures;
}

// Builds ranking.csv and the figures from whatever finished; prints the table and the
// missing and failed designs. Returns 0 if every design finished, else 1.
int collect(const std::string& out, bool print_table) {
  if (!io::file_exists(designs_csv(out)))
    throw InputError(out, "--collect", "a screen output folder (no designs.csv in it)");
  const io::KeyValues key = io::file_exists(key_path(out)) ? io::read_key_values(key_path(out)) : io::KeyValues{};
  const std::vector<Candidate> designs = read_designs(out);
  std::vector<DesignResult> results;
  for (const auto& c : designs) results.push_back(read_design_result(out, c));
  const auto ranked = rank_designs(results, io::find_value(key, "power") == "max");
  write_ranking(out, ranked);
  const std::string fig = render_screen_figures(out, ranked, key);

  int missing = 0, failed = 0;
  if (print_table) {
    std::printf("%4s %-10s %12s %10s %4s %10s %8s %12s %6s\n", "rank", "design", "life_h", "+-2sigma", "tie",
                "power_kW", "util", "loss/1000h", "front");
    for (const auto& r : ranked) {
      if (r.status != "finished") continue;
      std::printf("%4d %-10s %11.0f%s %10.0f %4s %10.4g %8.4f %12.1f %6s\n", r.rank, r.design.name.c_str(), r.life_h,
                  r.life_extrapolated ? "*" : " ", 2.0 * r.life_sigma_h, r.tied_with_best ? "=" : "",
                  r.power_kw, r.utilization, r.area_loss_mm2_per_1000h,
                  r.pareto_power && r.pareto_utilization ? "P,U" : r.pareto_power ? "P" : r.pareto_utilization ? "U" : "");
    }
    std::printf("(* life extrapolated; = tied with the best within 2 sigma; front P: life vs power, U: life vs "
                "utilisation)\n");
  }
  for (const auto& r : ranked) {
    if (r.status == "failed") {
      ++failed;
      std::fprintf(stderr, "millwear: design %s failed: %s\n", r.design.name.c_str(), r.reason.c_str());
    } else if (r.status == "missing") {
      ++missing;
      std::fprintf(stderr, "millwear: design %s missing: %s\n", r.design.name.c_str(), r.reason.c_str());
    }
  }
  if (!fig.empty()) std::fprintf(stderr, "millwear: warning: figures: %s\n", fig.c_str());
  std::printf("ranking: %s (%zu designs: %zu finished, %d failed, %d missing)\n", ranking_csv(out).c_str(),
              ranked.size(), ranked.size() - failed - missing, failed, missing);
  if (missing + failed > 0)
    std::printf("to finish: run the missing/failed tasks again (millwear screen-task %s I), or re-emit them "
                "with --emit, then --collect\n", out.c_str());
  return missing + failed > 0 ? 1 : 0;
}

// ---------------------------------------------------------------------------------------
// Local worker pool

std::atomic<int> g_screen_signal{0};
extern "C" void on_screen_signal(int sig) { g_screen_signal.store(sig); }

struct Pool {
  std::mutex mutex;
  std::set<pid_t> running_pids;
  int done = 0, failed = 0, running = 0;
};

// Runs `self screen-task OUT I` with output to log; returns its exit code (or 128 + signal).
int spawn_task(Pool& pool, const std::string& exe, const std::string& out, int index, const std::string& log) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&fa, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, STDOUT_FILENO, STDERR_FILENO);
  const std::string idx = std::to_string(index);
  std::vector<char*> argv{const_cast<char*>(exe.c_str()), const_cast<char*>("screen-task"),
                          const_cast<char*>(out.c_str()), const_cast<char*>(idx.c_str()), nullptr};
  pid_t pid = 0;
  int rc;
  {
    std::lock_guard<std::mutex> lock(pool.mutex);
    rc = posix_spawn(&pid, exe.c_str(), &fa, nullptr, argv.data(), environ);
    if (rc == 0) pool.running_pids.insert(pid);
  }
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) return 1;
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  {
    std::lock_guard<std::mutex> lock(pool.mutex);
    pool.running_pids.erase(pid);
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}

int run_pool(const ScreenArgs& args, const std::string& out, const std::vector<Candidate>& designs,
             const std::vector<int>& todo, int already_done) {
  const unsigned hw = std::max(1u, std::thread::hardware_concurrency());
  const int jobs = static_cast<int>(std::max<std::size_t>(1, std::min<std::size_t>(args.jobs > 0 ? args.jobs : hw, todo.size())));
  const std::string exe = self_exe();
  const std::string logs = io::join_path(out, "logs");
  io::ensure_dir(logs);
  Pool pool;
  pool.done = already_done;
  const bool live = !args.quiet && ::isatty(STDERR_FILENO);
  const int total = static_cast<int>(designs.size());

  struct sigaction sa {}, old_int {}, old_term {};
  sa.sa_handler = on_screen_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, &old_int);
  sigaction(SIGTERM, &sa, &old_term);
  g_screen_signal.store(0);

  const auto t0 = std::chrono::steady_clock::now();
  std::atomic<std::size_t> next{0};
  std::atomic<int> workers_left{jobs};
  std::vector<std::thread> workers;
  if (live)
    std::fprintf(stderr, "millwear screen: %d design(s), %zu to run, %d job(s), output %s\n", total, todo.size(), jobs,
                 out.c_str());
  for (int j = 0; j < jobs; ++j)
    workers.emplace_back([&] {
      for (std::size_t k; (k = next.fetch_add(1)) < todo.size();) {
        if (g_screen_signal.load() != 0) break;
        const int i = todo[k];
        {
          std::lock_guard<std::mutex> lock(pool.mutex);
          ++pool.running;
        }
        const Candidate& c = designs[static_cast<std::size_t>(i)];
        const int rc = spawn_task(pool, exe, out, i, io::join_path(logs, c.name + ".log"));
        const bool crashed = rc > 128 && g_screen_signal.load() == 0;
        if (crashed) {
          // The task died without a word (a crash, the OOM killer): say so in its status.
          try {
            write_task_status(out, c, "failed", rc,
                              "the task died with signal " + std::to_string(rc - 128) + " (see logs/" + c.name + ".log)");
          } catch (const std::exception&) {
          }
        }
        std::lock_guard<std::mutex> lock(pool.mutex);
        --pool.running;
        if (rc == 0) ++pool.done;
        else if (rc == 1 || rc == 2 || crashed) ++pool.failed;
      }
      workers_left.fetch_sub(1);
    });
  auto print_progress = [&] {
    std::lock_guard<std::mutex> lock(pool.mutex);
    const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const int fresh = pool.done + pool.failed - already_done;
    const int left = total - pool.done - pool.failed;
    const double eta = fresh > 0 ? el * left / fresh : std::nan("");
    std::fprintf(stderr, "\r\x1b[Kscreen: %d/%d done, %d running, %d failed, elapsed %s, left %s", pool.done, total,
                 pool.running, pool.failed, duration_text(el).c_str(), duration_text(eta).c_str());
    std::fflush(stderr);
  };
  int last_signal = 0;
  while (workers_left.load() > 0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
    const int sig = g_screen_signal.load();
    if (sig != 0 && sig != last_signal) {
      // Ctrl-C from a terminal reaches the tasks too; a SIGTERM to this process alone is
      // passed on to the tasks it started, by their process ids.
      std::lock_guard<std::mutex> lock(pool.mutex);
      if (sig == SIGTERM)
        for (pid_t p : pool.running_pids) kill(p, SIGTERM);
      last_signal = sig;
    }
    if (live) print_progress();
  }
  for (auto& w : workers) w.join();
  if (live) {
    // The last design may finish after the last tick: the line ends with the final counts.
    print_progress();
    std::fprintf(stderr, "\n");
  }
  sigaction(SIGINT, &old_int, nullptr);
  sigaction(SIGTERM, &old_term, nullptr);
  const int sig = g_screen_signal.load();
  if (sig != 0) {
    std::fprintf(stderr,
                 "millwear: screen interrupted; finished designs and stages are kept in %s. Run the same command "
                 "with --resume to continue.\n",
                 out.c_str());
    return 128 + sig;
  }
  return 0;
}

// ---------------------------------------------------------------------------------------
// The screen command

int screen_command(const ScreenArgs& args) {
  std::error_code ec;
  if (args.collect) {
    const std::string out = !args.out.empty() ? args.out : args.screen;
    if (out.empty()) throw InputError("", "--collect", "the screen's output folder: --collect -o OUT (or --collect OUT)");
    std::optional<io::FolderLock> lock;  // ranking and figures: one writer at a time
    if (fs::is_directory(out, ec)) lock.emplace(out);
    return collect(out, true);
  }
  if (args.screen.empty()) throw InputError("", "SCREEN", "a screen file (or --collect OUT)");
  if (args.out.empty()) throw InputError("", "-o", "an output folder");
  if (!args.emit.empty() && args.emit != "parallel" && args.emit != "slurm")
    throw InputError("", "--emit", "parallel or slurm, got '" + args.emit + "'");
  const std::string& out = args.out;
  if (fs::exists(out, ec) && !fs::is_directory(out, ec))
    throw InputError(out, "-o", "an output folder, but a file of that name exists");

  // Everything validated before anything is written.
  const ScreenDef def = load_screen(args.screen);
  const Scene base = load_scene(def.base_scene);
  std::vector<Candidate> cands = sample_family(def, base);
  const std::vector<std::string> varying = varying_parameters(def);

  // Fingerprint: the screen file, the base scene, the candidates' profiles and the build.
  std::string all = std::string(MILLWEAR_VERSION) + "\n" + io::read_file(args.screen) + "\n--\n" + io::read_file(def.base_scene);
  for (const auto& p : def.profiles) all += "\n--\n" + io::read_file(p);
  if (!def.equal_area.empty() && def.equal_area != "base") all += "\n--\n" + io::read_file(def.equal_area);
  const std::string fingerprint = io::stable_hash_hex(all);
  const io::FolderLock lock(out);  // one screen per folder, from here to the ranking
  bool same = false;
  if (io::file_exists(key_path(out))) {
    same = io::find_value(io::read_key_values(key_path(out)), "fingerprint") == fingerprint;
    if (!same && (args.resume || !args.emit.empty()) && fs::exists(io::join_path(out, "designs"), ec))
      throw InputError(key_path(out), "fingerprint",
                       "the same screen file, base scene and profiles as the screen in this folder (they changed); "
                       "use a new output folder or run without --resume/--emit to start over");
  }
  const bool keep = same && (args.resume || !args.emit.empty());
  if (!keep) {
    fs::remove_all(io::join_path(out, "designs"), ec);
    fs::remove_all(io::join_path(out, "candidates"), ec);
    fs::remove_all(io::join_path(out, "logs"), ec);
    fs::remove_all(io::join_path(out, "slurm"), ec);
    fs::remove_all(io::join_path(out, "plots"), ec);
    for (const char* f : {"jobs.txt", "screen.sbatch", "ranking.csv"}) fs::remove(io::join_path(out, f), ec);
  }
  io::ensure_dir(out);
  io::ensure_dir(io::join_path(out, "inputs"));
  io::write_file_atomic(io::join_path(io::join_path(out, "inputs"), fs::path(args.screen).filename().string()),
                        io::read_file(args.screen));
  write_candidates(def, cands, out);
  write_design_tables(out, cands);
  std::string vary;
  for (const auto& v : varying) vary += (vary.empty() ? "" : " ") + v;
  io::write_file_atomic(key_path(out), io::format_key_values({{"fingerprint", fingerprint},
                                                              {"name", def.name},
                                                              {"screen_file", abs_path(args.screen)},
                                                              {"power", def.power_higher_is_better ? "max" : "min"},
                                                              {"varying", vary}},
                                                             "millwear screen (for --resume, --emit, --collect)"));
  const std::vector<Candidate> designs = read_designs(out);
  const std::size_t rejected = cands.size() - designs.size();
  if (designs.empty()) {
    std::string first;
    for (const auto& c : cands)
      if (!c.reason.empty()) { first = c.name + ": " + c.reason; break; }
    throw InputError(args.screen, "family",
                     "at least one valid candidate; all " + std::to_string(cands.size()) + " were rejected (see " +
                         rejected_csv(out) + "; first: " + first + ")");
  }
  std::printf("screen %s: %zu candidate(s), %zu valid, %zu rejected (%s)\n", def.name.c_str(), cands.size(),
              designs.size(), rejected, rejected_csv(out).c_str());

  std::vector<int> todo;
  int already = 0;
  for (std::size_t i = 0; i < designs.size(); ++i) {
    if (keep && design_finished(out, designs[i])) ++already;
    else todo.push_back(static_cast<int>(i));
  }

  if (!args.emit.empty() && todo.empty()) {
    std::error_code rm;
    fs::remove(io::join_path(out, args.emit == "parallel" ? "jobs.txt" : "screen.sbatch"), rm);
    std::printf("every design has finished: nothing to emit; rank them with millwear screen --collect %s\n", out.c_str());
    return 0;
  }
  if (!args.emit.empty()) {
    EmitOptions o;
    o.binary = self_exe();
    o.out = abs_path(out);
    o.name = def.name;
    o.chunk = std::max(1, args.chunk);
    o.max_running = args.jobs;
    if (args.emit == "parallel") {
      const std::string path = io::join_path(out, "jobs.txt");
      io::write_file_atomic(path, parallel_job_list(todo, o));
      std::printf("%zu job(s) (%zu design(s), %d already finished) in %s\nrun:  parallel -j N < %s\nthen: %s screen "
                  "--collect %s\n",
                  chunk_tasks(todo, o.chunk).size(), todo.size(), already, path.c_str(), path.c_str(), o.binary.c_str(),
                  out.c_str());
    } else {
      io::ensure_dir(io::join_path(out, "slurm"));
      std::string tasks;
      const std::string script = slurm_script(todo, o, tasks);
      io::write_file_atomic(io::join_path(io::join_path(out, "slurm"), "tasks.txt"), tasks);
      const std::string path = io::join_path(out, "screen.sbatch");
      io::write_file_atomic(path, script);
      std::printf("%zu array task(s) (%zu design(s), %d already finished) in %s\nrun:  sbatch %s\nthen: %s screen "
                  "--collect %s\n",
                  chunk_tasks(todo, o.chunk).size(), todo.size(), already, path.c_str(), path.c_str(),
                  o.binary.c_str(), out.c_str());
    }
    return 0;
  }

  if (!todo.empty()) {
    const int rc = run_pool(args, out, designs, todo, already);
    if (rc != 0) return rc;
  }
  return collect(out, true);
}

}  // namespace

void register_screen(CLI::App& app, Action* action) {
  auto args = std::make_shared<ScreenArgs>();
  CLI::App* cmd = app.add_subcommand(
      "screen", "Screen a family of lifter designs: run each (locally, or via GNU parallel / Slurm), rank by life with "
                "uncertainty, Pareto fronts, figures");
  cmd->footer(
      "Screen file: [screen] base = \"scene.toml\", sampling = \"grid\"|\"latin_hypercube\", equal_area, ...;\n"
      "[family] height, top_width, leading_face_angle, trailing_face_angle, rows, direction (see docs/screen.md).\n"
      "OUT: designs.csv, rejected.csv, candidates/, designs/NAME/ (a `millwear run` folder each), ranking.csv, plots/.\n"
      "Exit codes: 0 all ranked, 1 a design failed or is missing, 2 bad input, 130/143 interrupted (--resume).");
  cmd->add_option("screen", args->screen, "screen file (TOML); with --collect: the output folder");
  cmd->add_option("-o,--out", args->out, "output folder")->check(output_folder());
  cmd->add_option("-j,--jobs", args->jobs, "designs run at once (default: hardware cores); with --emit slurm: %M")
      ->check(CLI::Range(1, 1024));
  cmd->add_flag("--resume", args->resume, "keep finished designs (and finished stages) in OUT, run the rest");
  cmd->add_option("--emit", args->emit, "parallel | slurm: write a job list / sbatch array script instead of running");
  cmd->add_option("--chunk", args->chunk, "designs per job or array task (with --emit)")->check(CLI::Range(1, 100000));
  cmd->add_flag("--collect", args->collect, "rank whatever finished in OUT; list missing and failed designs");
  cmd->add_flag("-q,--quiet", args->quiet, "no live progress");
  cmd->callback([args, action] { *action = [args] { return screen_command(*args); }; });
}

void register_screen_task(CLI::App& app, Action* action) {
  auto out = std::make_shared<std::string>();
  auto idx = std::make_shared<std::vector<int>>();
  CLI::App* cmd = app.add_subcommand(
      "screen-task", "Run design(s) I of a screen's OUT/designs.csv into OUT/designs/NAME (what GNU parallel and Slurm "
                     "array tasks run)");
  cmd->add_option("out", *out, "the screen's output folder")->required()->check(output_folder());
  cmd->add_option("task", *idx, "task numbers (rows of designs.csv, from 0)")->required();
  cmd->callback([out, idx, action] { *action = [out, idx] { return screen_task_command(*out, *idx); }; });
}

}  // namespace millwear::app
