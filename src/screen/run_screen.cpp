// `millwear screen` as one call (see run_screen.hpp).
#include "screen/run_screen.hpp"

#include <algorithm>
#include <filesystem>
#include <memory>

#include "common/errors.hpp"
#include "io/atomic_write.hpp"
#include "io/folder_lock.hpp"
#include "io/hash.hpp"
#include "io/run_folder.hpp"
#include "screen/jobs.hpp"
#include "screen/ranking.hpp"
#include "screen/task.hpp"
#include "study/plan.hpp"
#include "study/run_designs.hpp"

namespace millwear::screen {

namespace fs = std::filesystem;

namespace {

std::string abs_path(const std::string& p) { return fs::absolute(p).lexically_normal().string(); }

// The screen file, the base scene, the candidates' profiles and the build.
std::string screen_fingerprint(const std::string& screen_file, const ScreenDef& def, int replicates) {
  std::string all = std::string(MILLWEAR_VERSION) + "\n" + io::read_file(screen_file) + "\n--\n" +
                    io::read_file(def.base_scene);
  for (const auto& p : def.profiles) all += "\n--\n" + io::read_file(p);
  if (!def.equal_area.empty() && def.equal_area != "base" && def.equal_area_kinds.empty())
    all += "\n--\n" + io::read_file(def.equal_area);
  for (const auto& p : def.equal_area_kinds) all += "\n--\n" + io::read_file(p);
  for (const auto& o : def.overrides) all += "\n--set " + o;  // written into every candidate
  if (replicates > 1) all += "\n--replicates " + std::to_string(replicates);  // the tasks' histories
  return io::stable_hash_hex(all);
}

// A candidate's name as the screen gives it: d and three or five digits.
bool is_candidate_name(const std::string& name) {
  if ((name.size() != 4 && name.size() != 6) || name[0] != 'd') return false;
  return std::all_of(name.begin() + 1, name.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// A file the screen writes for a candidate under candidates/ or logs/: NAME.toml,
// NAME-profile.toml or .csv, NAME-kK-profile.toml, NAME.log.
bool is_candidate_file(const std::string& file) {
  const std::size_t end = file.find_first_of(".-");
  if (end == std::string::npos || !is_candidate_name(file.substr(0, end))) return false;
  const std::string rest = file.substr(end);
  if (rest == ".toml" || rest == ".log" || rest == "-profile.toml" || rest == "-profile.csv") return true;
  // -kK-profile.toml
  const std::string tail = "-profile.toml";
  if (rest.size() <= 2 + tail.size() || rest.compare(0, 2, "-k") != 0 ||
      rest.compare(rest.size() - tail.size(), tail.size(), tail) != 0)
    return false;
  const std::string k = rest.substr(2, rest.size() - 2 - tail.size());
  return std::all_of(k.begin(), k.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// Removes the entries of DIR for which `ours` holds (regular files only, none of `keep`), then
// DIR if that leaves it empty.
template <class Pred>
void remove_ours(const std::string& dir, const std::vector<std::string>& keep, const Pred& ours) {
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(dir, ec))) return;  // a linked folder's files are elsewhere
  std::vector<fs::path> found;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file(ec) && !it->is_symlink(ec) && ours(it->path().filename().string()) &&
        !io::is_one_of(it->path().string(), keep))
      found.push_back(it->path());
  for (const auto& f : found) fs::remove(f, ec);
  io::remove_stale_temps(dir);
  if (fs::is_empty(dir, ec)) fs::remove(dir, ec);
}

// The files an earlier screen wrote in OUT, and the folders they leave empty: each design's
// run (the files its manifest lists) and task status, the candidates' files and logs, the
// Slurm task list and logs, the job lists, the tables, the ranking, the figures and the copy
// of the screen file. A user's own files, in OUT or any of its folders, stay, and so do the
// files of `keep` (the inputs this screen reads, which may be copies in OUT).
void remove_screen_outputs(const std::string& out, const io::KeyValues& key, const std::vector<std::string>& keep,
                           bool same_screen) {
  std::error_code ec;
  const std::string designs = io::join_path(out, "designs");
  if (fs::is_directory(fs::symlink_status(designs, ec))) {
    std::vector<std::string> dirs;
    for (fs::directory_iterator it(designs, ec), end; !ec && it != end; it.increment(ec))
      if (it->is_directory(ec) && !it->is_symlink(ec) && is_candidate_name(it->path().filename().string()))
        dirs.push_back(it->path().string());
    // A design a task still runs (a GNU parallel or Slurm job) is that task's: nothing of the
    // screen is removed while one is. Each design's lock is held while its files go, so a
    // task that starts meanwhile is refused instead of losing its files.
    std::vector<std::unique_ptr<io::FolderLock>> locks;
    for (const auto& dir : dirs) {
      try {
        locks.push_back(std::make_unique<io::FolderLock>(dir));
      } catch (const InputError&) {
        throw InputError(dir, "-o",
                         "a screen folder no task is writing into, but " + io::folder_holder(dir) +
                             " holds this design; wait for it " +
                             (same_screen ? "to end, or use --resume to run the other designs"
                                          : "to end, or use a new output folder"));
      }
    }
    for (const auto& dir : dirs) {
      study::remove_run_outputs(dir, keep);
      remove_ours(dir, keep, [](const std::string& f) { return f == "task.status"; });
    }
    locks.clear();
    for (const auto& dir : dirs) fs::remove(dir, ec);  // only if the release left it empty
    if (fs::is_empty(designs, ec)) fs::remove(designs, ec);
  }
  remove_ours(io::join_path(out, "candidates"), keep, is_candidate_file);
  remove_ours(io::join_path(out, "logs"), keep, is_candidate_file);
  remove_ours(io::join_path(out, "slurm"), keep, [](const std::string& f) {
    return f == "tasks.txt" || (f.rfind("task-", 0) == 0 && f.size() > 4 && f.compare(f.size() - 4, 4, ".out") == 0);
  });
  const std::string plots = io::join_path(out, "plots");
  remove_ours(io::join_path(plots, "data"), keep, [](const std::string& f) { return f == "top_profiles.dat" || f == "heatmap.dat"; });
  remove_ours(plots, keep, [](const std::string& f) {
    if (f == "gnuplot.log") return true;
    for (const char* fig : {"screen_pareto", "screen_top_profiles", "screen_heatmap"})
      for (const char* ext : {".png", ".svg"})
        if (f == std::string(fig) + ext) return true;
    return false;
  });
  const std::string copied = fs::path(io::find_value(key, "screen_file")).filename().string();
  remove_ours(io::join_path(out, "inputs"), keep, [&copied](const std::string& f) { return !copied.empty() && f == copied; });
  for (const std::string& f : {io::join_path(out, "jobs.txt"), io::join_path(out, "screen.sbatch"), ranking_csv(out),
                               designs_csv(out), rejected_csv(out), screen_key_path(out)})
    if (!io::is_one_of(f, keep)) fs::remove(f, ec);
}

// Every file a screen reads: its own, the base scene, the listed profiles and the areas' files.
std::vector<std::string> screen_inputs(const std::string& screen_file, const ScreenDef& def) {
  std::vector<std::string> files{screen_file, def.base_scene};
  files.insert(files.end(), def.profiles.begin(), def.profiles.end());
  if (!def.equal_area.empty() && def.equal_area != "base" && def.equal_area_kinds.empty()) files.push_back(def.equal_area);
  files.insert(files.end(), def.equal_area_kinds.begin(), def.equal_area_kinds.end());
  return files;
}

}  // namespace

ScreenInputs read_screen_inputs(const ScreenRequest& a) {
  if (a.screen_file.empty()) throw InputError("", "SCREEN", "a screen file (or --collect OUT)");
  if (a.out.empty()) throw InputError("", "-o", "an output folder");
  if (!a.emit.empty() && a.emit != "parallel" && a.emit != "slurm")
    throw InputError("", "--emit", "parallel or slurm, got '" + a.emit + "'");
  const std::string& out = a.out;
  std::error_code ec;
  if (fs::exists(out, ec) && !fs::is_directory(out, ec))
    throw InputError(out, "-o", "an output folder, but a file of that name exists");

  // Everything validated before anything is written.
  ScreenInputs in;
  in.def = load_screen(a.screen_file, a.overrides);
  const Scene base = load_scene(in.def.base_scene, a.overrides);
  in.candidates = sample_family(in.def, base);
  check_distinct_candidates(in.candidates, a.screen_file);
  in.varying = varying_parameters(in.def);
  if (a.replicates < 1 || a.replicates > study::kMaxReplicates)
    throw InputError("", "--replicates", "1 to " + std::to_string(study::kMaxReplicates) +
                                             " histories per design, got " + std::to_string(a.replicates));
  // Each design's replicates take the base scene's seeds s .. s + N - 1 (as `run`'s).
  check_derived_seeds(base, static_cast<std::uint64_t>(a.replicates), "--replicates " + std::to_string(a.replicates));
  in.fingerprint = screen_fingerprint(a.screen_file, in.def, a.replicates);
  return in;
}

// The key's record of an input file: its absolute path and a hash of its contents.
std::string input_record(const std::string& file) {
  return abs_path(file) + " " + io::stable_hash_hex(io::read_file(file));
}

// What of a screen's inputs differs from those its key recorded: the --set overrides,
// --replicates, the program's version, each input file (another file, or its contents);
// a key without those records says only that something did.
std::string key_changes(const io::KeyValues& have, const ScreenRequest& a, const ScreenDef& def) {
  std::vector<std::string> sets, inputs_then;
  for (const auto& [k, v] : have) {
    if (k == "set") sets.push_back(v);
    if (k == "input") inputs_then.push_back(v);
  }
  std::vector<std::string> changed;
  if (sets != def.overrides) changed.push_back("--set overrides");
  if (io::find_value(have, "replicates") != std::to_string(a.replicates)) changed.push_back("--replicates");
  const std::string version = io::find_value(have, "version");
  if (!version.empty() && version != MILLWEAR_VERSION)
    changed.push_back("the millwear version (" + version + " then, " + MILLWEAR_VERSION + " now)");
  if (!inputs_then.empty()) {
    const std::vector<std::string> files = screen_inputs(a.screen_file, def);
    const auto path_of = [](const std::string& record) { return record.substr(0, record.rfind(' ')); };
    for (std::size_t i = 0; i < std::max(files.size(), inputs_then.size()); ++i) {
      const std::string now = i < files.size() ? input_record(files[i]) : "";
      const std::string then = i < inputs_then.size() ? inputs_then[i] : "";
      if (now == then) continue;
      if (!now.empty() && !then.empty() && path_of(now) == path_of(then)) changed.push_back("the contents of " + path_of(now));
      else changed.push_back("input " + std::to_string(i + 1) + " (" + (then.empty() ? "none" : path_of(then)) + " then, " +
                             (now.empty() ? "none" : path_of(now)) + " now)");
    }
  }
  std::string text;
  for (const auto& c : changed) text += (text.empty() ? "" : ", ") + c;
  return text.empty() ? "the contents of the screen file, base scene or profiles, or the millwear version, changed"
                      : text + " changed";
}

ScreenSetup prepare_screen(const ScreenRequest& a, const ScreenInputs& in) {
  const std::string& out = a.out;
  const ScreenDef& def = in.def;
  const std::string& fingerprint = in.fingerprint;
  std::vector<Candidate> cands = in.candidates;
  std::error_code ec;
  const std::string key_file = screen_key_path(out);
  bool same = false;
  io::KeyValues have;
  if (io::file_exists(key_file)) {
    have = io::read_key_values(key_file);
    same = io::find_value(have, "fingerprint") == fingerprint;
    const std::string what = "the same screen file, base scene, profiles, --set overrides and --replicates as the "
                             "screen in this folder (" + key_changes(have, a, def) + "); ";
    // Its candidates may be queued already (an emitted job list): a screen of other inputs
    // would have them run other scenes.
    if (!same && (a.resume || !a.emit.empty()))
      throw InputError(key_file, "fingerprint",
                       what + "use a new output folder, or run without --resume/--emit and with --force to start over");
    // Another screen's results are not replaced unasked.
    if (!same && !a.force)
      throw InputError(key_file, "fingerprint",
                       what + "use a new output folder, or --force to delete that screen's files (those it wrote; "
                              "no other file) and start over");
  }
  const bool keep = same && (a.resume || !a.emit.empty());
  if (!keep) remove_screen_outputs(out, have, screen_inputs(a.screen_file, def), same);
  const bool out_existed = fs::exists(out, ec);
  const bool inputs_existed = fs::exists(io::join_path(out, "inputs"), ec);
  io::ensure_dir(out);
  io::ensure_dir(io::join_path(out, "inputs"));
  const std::string input_copy =
      io::join_path(io::join_path(out, "inputs"), fs::path(a.screen_file).filename().string());
  io::write_file_atomic(input_copy, io::read_file(a.screen_file));
  write_candidates(def, cands, out);
  write_design_tables(out, cands);
  std::string vary;
  for (const auto& v : in.varying) vary += (vary.empty() ? "" : " ") + v;
  io::KeyValues key{{"fingerprint", fingerprint},
                    {"name", def.name},
                    {"screen_file", abs_path(a.screen_file)},
                    {"power", def.power_higher_is_better ? "max" : "min"},
                    {"varying", vary},
                    {"replicates", std::to_string(a.replicates)},
                    // The list as written: every command that reads it after checks it is.
                    {"designs", io::stable_hash_hex(io::read_file(designs_csv(out)))}};
  for (const auto& o : def.overrides) key.emplace_back("set", o);  // in order, as given
  // What the fingerprint holds, each on its own: a folder of another screen says what changed.
  key.emplace_back("version", MILLWEAR_VERSION);
  for (const std::string& f : screen_inputs(a.screen_file, def)) key.emplace_back("input", input_record(f));
  io::write_file_atomic(key_file, io::format_key_values(key, "millwear screen (for --resume, --emit, --collect)"));
  ScreenSetup s;
  s.name = def.name;
  s.designs = read_designs(out);
  s.candidates = cands.size();
  s.rejected = cands.size() - s.designs.size();
  if (s.designs.empty()) {
    // Candidates are validated by writing and reading them back; a refusal takes back all of it.
    std::string first;
    for (const auto& c : cands)
      if (!c.reason.empty()) { first = c.name + ": " + c.reason; break; }
    fs::remove_all(io::join_path(out, "candidates"), ec);
    for (const std::string& f : {designs_csv(out), rejected_csv(out), key_file, input_copy}) fs::remove(f, ec);
    if (!inputs_existed) fs::remove(io::join_path(out, "inputs"), ec);  // only if empty
    if (!out_existed) fs::remove(out, ec);
    throw InputError(a.screen_file, "family",
                     "at least one valid candidate; all " + std::to_string(cands.size()) + " were rejected (first: " +
                         first + ")");
  }
  for (std::size_t i = 0; i < s.designs.size(); ++i) {
    // Finished, and its results read: a finished design whose summary is gone or unreadable
    // runs again (it continues its stages), as --collect advises.
    if (keep && design_finished(out, s.designs[i], true) && read_design_result(out, s.designs[i]).status == "finished")
      ++s.already_done;
    else s.todo.push_back(static_cast<int>(i));
  }
  return s;
}

EmitOutcome emit_jobs(const ScreenRequest& a, const ScreenSetup& s) {
  EmitOutcome e;
  const std::string& out = a.out;
  if (s.todo.empty()) {
    std::error_code rm;
    fs::remove(io::join_path(out, a.emit == "parallel" ? "jobs.txt" : "screen.sbatch"), rm);
    return e;
  }
  EmitOptions o;
  o.binary = a.exe.empty() ? self_executable() : a.exe;
  o.out = abs_path(out);
  o.name = s.name;
  o.chunk = std::max(1, a.chunk);
  o.max_running = a.jobs;
  e.binary = o.binary;
  e.jobs = chunk_tasks(s.todo, o.chunk).size();
  if (a.emit == "parallel") {
    e.path = io::join_path(out, "jobs.txt");
    io::write_file_atomic(e.path, parallel_job_list(s.todo, o));
  } else {
    io::ensure_dir(io::join_path(out, "slurm"));
    std::string tasks;
    const std::string script = slurm_script(s.todo, o, tasks);
    io::write_file_atomic(io::join_path(io::join_path(out, "slurm"), "tasks.txt"), tasks);
    e.path = io::join_path(out, "screen.sbatch");
    io::write_file_atomic(e.path, script);
  }
  return e;
}

ScreenOutcome run_screen(const ScreenRequest& a, const std::atomic<int>* stop_signal, const ScreenCallbacks& cb) {
  ScreenOutcome o;
  const ScreenInputs inputs = read_screen_inputs(a);
  const io::FolderLock lock(a.out, "screen");  // one screen per folder, from here to the ranking
  o.setup = prepare_screen(a, inputs);
  if (cb.on_setup) cb.on_setup(o.setup);
  if (!a.emit.empty()) {
    o.emitted = true;
    o.emit = emit_jobs(a, o.setup);
    return o;
  }
  if (!o.setup.todo.empty()) {
    PoolOptions p;
    p.exe = a.exe;
    p.jobs = a.jobs;
    p.stop_signal = stop_signal;
    p.on_start = cb.on_pool_start;
    p.on_tick = cb.on_pool_tick;
    p.on_end = cb.on_pool_end;
    o.signal = run_task_pool(a.out, o.setup.designs, o.setup.todo, o.setup.already_done, p).signal;
    if (o.signal != 0) return o;
  }
  o.collected = collect_screen(a.out, false);  // the lock is held
  return o;
}

}  // namespace millwear::screen
