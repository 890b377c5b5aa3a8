// `millwear screen` as one call (see run_screen.hpp).
#include "screen/run_screen.hpp"

#include <algorithm>
#include <filesystem>

#include "common/errors.hpp"
#include "io/atomic_write.hpp"
#include "io/folder_lock.hpp"
#include "io/hash.hpp"
#include "io/run_folder.hpp"
#include "screen/jobs.hpp"
#include "screen/task.hpp"
#include "study/plan.hpp"

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
  in.varying = varying_parameters(in.def);
  if (a.replicates < 1 || a.replicates > study::kMaxReplicates)
    throw InputError("", "--replicates", "1 to " + std::to_string(study::kMaxReplicates) +
                                             " histories per design, got " + std::to_string(a.replicates));
  in.fingerprint = screen_fingerprint(a.screen_file, in.def, a.replicates);
  return in;
}

// What of a screen's inputs differs from those its key recorded: the --set overrides or
// --replicates; otherwise the contents of its files (or the program's version).
std::string key_changes(const io::KeyValues& have, const ScreenRequest& a, const ScreenDef& def) {
  std::vector<std::string> sets;
  for (const auto& [k, v] : have)
    if (k == "set") sets.push_back(v);
  std::vector<std::string> changed;
  if (sets != def.overrides) changed.push_back("--set overrides");
  if (io::find_value(have, "replicates") != std::to_string(a.replicates)) changed.push_back("--replicates");
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
  if (io::file_exists(key_file)) {
    const io::KeyValues have = io::read_key_values(key_file);
    same = io::find_value(have, "fingerprint") == fingerprint;
    // Its candidates may be queued already (an emitted job list): a screen of other inputs
    // would have them run other scenes.
    if (!same && (a.resume || !a.emit.empty()))
      throw InputError(key_file, "fingerprint",
                       "the same screen file, base scene, profiles, --set overrides and --replicates as the screen in "
                       "this folder (" + key_changes(have, a, def) + "); "
                       "use a new output folder or run without --resume/--emit to start over");
  }
  const bool keep = same && (a.resume || !a.emit.empty());
  if (!keep) {
    fs::remove_all(io::join_path(out, "designs"), ec);
    fs::remove_all(io::join_path(out, "candidates"), ec);
    fs::remove_all(io::join_path(out, "logs"), ec);
    fs::remove_all(io::join_path(out, "slurm"), ec);
    fs::remove_all(io::join_path(out, "plots"), ec);
    for (const char* f : {"jobs.txt", "screen.sbatch", "ranking.csv"}) fs::remove(io::join_path(out, f), ec);
  }
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
                    {"replicates", std::to_string(a.replicates)}};
  for (const auto& o : def.overrides) key.emplace_back("set", o);  // in order, as given
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
    if (keep && design_finished(out, s.designs[i])) ++s.already_done;
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
