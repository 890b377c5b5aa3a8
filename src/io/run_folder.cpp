#include "io/run_folder.hpp"

#include "common/names.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "common/errors.hpp"
#include "common/text.hpp"
#include "io/atomic_write.hpp"

namespace millwear::io {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// ---- paths ----

std::string join_path(const std::string& a, const std::string& b) {
  if (a.empty()) return b;
  if (a.back() == '/') return a + b;
  return a + "/" + b;
}

std::string manifest_path(const std::string& out) { return join_path(out, "manifest.json"); }
std::string summary_path(const std::string& out) { return join_path(out, "summary.csv"); }
std::string spectrum_path(const std::string& out) { return join_path(out, "spectrum.csv"); }
std::string profiles_dir(const std::string& out) { return join_path(out, "profiles"); }
std::string profile_path(const std::string& out, const std::string& design, int stage) {
  return join_path(profiles_dir(out), design + "_stage" + std::to_string(stage) + ".csv");
}
std::string snapshot_path(const std::string& out, const std::string& design) {
  return join_path(out, "snapshot_" + design + ".csv");
}
std::string liner_path(const std::string& out, const std::string& design) {
  return join_path(out, "liner_" + design + ".csv");
}
std::string stages_dir(const std::string& out) { return join_path(out, "stages"); }
std::string run_key_path(const std::string& out) { return join_path(stages_dir(out), "run.key"); }
std::string stage_done_marker(const std::string& out, const std::string& design, int stage) {
  return join_path(stages_dir(out), design + "_stage" + std::to_string(stage) + ".done");
}
std::string plots_out_dir(const std::string& out) { return join_path(out, "plots"); }
std::string plots_data_dir(const std::string& out) { return join_path(plots_out_dir(out), "data"); }

bool is_valid_design_name(const std::string& design) { return is_safe_name(design); }

void create_run_folder(const std::string& out) {
  ensure_dir(out);
  ensure_dir(profiles_dir(out));
  ensure_dir(stages_dir(out));
  ensure_dir(plots_out_dir(out));
  ensure_dir(plots_data_dir(out));
}

std::string relative_to(const std::string& out, const std::string& path) {
  if (out.empty()) return "";
  // Compared as normal paths: OUT given as "out/" and a file as "out//x.csv" are still inside.
  const fs::path rel = fs::path(path).lexically_normal().lexically_relative(fs::path(out).lexically_normal());
  if (rel.empty() || rel == "." || *rel.begin() == "..") return "";
  return rel.generic_string();
}

namespace {

// A manifest's entry that names a path inside its folder: relative, without a ".." part, and
// through no symbolic link (a linked folder's files are elsewhere).
bool inside_folder(const std::string& out, const std::string& f) {
  const fs::path rel(f);
  if (f.empty() || rel.is_absolute()) return false;
  for (const auto& part : rel)
    if (part == "..") return false;
  std::error_code ec;
  for (fs::path p = rel.parent_path(); !p.empty(); p = p.parent_path())
    if (fs::is_symlink(fs::symlink_status(join_path(out, p.string()), ec))) return false;
  return true;
}

// A folder of OUT itself (not a link to one elsewhere).
bool is_own_dir(const std::string& d) {
  std::error_code ec;
  return fs::is_directory(fs::symlink_status(d, ec));
}

}  // namespace

bool is_one_of(const std::string& path, const std::vector<std::string>& files) {
  std::error_code ec;
  for (const auto& f : files)
    if (fs::equivalent(path, f, ec)) return true;
  return false;
}

int remove_run_files(const std::string& out, const std::vector<std::string>& files,
                     const std::vector<std::string>& keep) {
  int removed = 0;
  std::error_code ec;
  std::vector<fs::path> parents;  // of the listed files, to remove where left empty
  for (const auto& f : files) {
    if (!inside_folder(out, f)) continue;
    const std::string path = join_path(out, f);
    if (fs::is_regular_file(fs::symlink_status(path, ec)) && !is_one_of(path, keep) && fs::remove(path, ec)) ++removed;
    for (fs::path p = fs::path(f).parent_path(); !p.empty(); p = p.parent_path()) parents.push_back(p);
  }
  std::vector<std::string> dirs;
  for (const std::string& d : {plots_data_dir(out), plots_out_dir(out), stages_dir(out), profiles_dir(out),
                               join_path(out, "inputs")})
    if (is_own_dir(d)) dirs.push_back(d);
  removed += remove_stale_temps(out);
  for (const auto& d : dirs) removed += remove_stale_temps(d);
  for (const auto& d : dirs)
    if (fs::is_empty(d, ec)) fs::remove(d, ec);
  // The folders the listed files leave empty (a sweep's points/NN, a vtk series), deepest
  // first; OUT itself stays.
  std::sort(parents.begin(), parents.end(), [](const fs::path& a, const fs::path& b) {
    const auto depth = [](const fs::path& p) { return std::distance(p.begin(), p.end()); };
    return depth(a) != depth(b) ? depth(a) > depth(b) : a < b;
  });
  parents.erase(std::unique(parents.begin(), parents.end()), parents.end());
  for (const auto& p : parents) {
    const std::string d = join_path(out, p.string());
    if (is_own_dir(d) && fs::is_empty(d, ec)) fs::remove(d, ec);
  }
  return removed;
}

std::string unlisted_output(const std::string& out, const std::vector<std::string>& names) {
  std::error_code ec;
  // Without a manifest (an older millwear's folder, or none) nothing tells its files apart.
  if (!fs::is_directory(out, ec) || !file_exists(manifest_path(out))) return "";
  const std::vector<std::string> listed = manifest_files(out);
  for (const std::string& n : names)
    if (std::find(listed.begin(), listed.end(), n) == listed.end() &&
        fs::exists(fs::symlink_status(join_path(out, n), ec)))
      return join_path(out, n);
  return "";
}

// ---- key=value ----

namespace {

bool parse_int(const std::string& s, int* out) {
  if (s.empty() || s.size() > 9) return false;
  for (char c : s)
    if (!std::isdigit(static_cast<unsigned char>(c))) return false;
  *out = std::atoi(s.c_str());
  return true;
}

}  // namespace

std::string format_key_values(const KeyValues& kv, const std::string& comment) {
  std::string s;
  if (!comment.empty()) s += "# " + comment + "\n";
  for (const auto& [k, v] : kv) {
    if (k.empty() || k.find_first_of("=\r\n#") != std::string::npos || trim(k) != k)
      throw std::invalid_argument("bad key for a key=value file: '" + k + "'");
    if (v.find_first_of("\r\n") != std::string::npos)
      throw std::invalid_argument("value of '" + k + "' contains a line end");
    s += k + "=" + v + "\n";
  }
  return s;
}

KeyValues parse_key_values(const std::string& text, const std::string& name) {
  KeyValues kv;
  std::size_t line_no = 0, i = 0;
  while (i <= text.size()) {
    std::size_t e = text.find('\n', i);
    if (e == std::string::npos) e = text.size();
    std::string line = text.substr(i, e - i);
    ++line_no;
    i = e + 1;
    std::string t = trim(line);
    if (t.empty() || t[0] == '#') {
      if (e == text.size()) break;
      continue;
    }
    std::size_t eq = t.find('=');
    if (eq == std::string::npos || trim(t.substr(0, eq)).empty())
      throw InputError(name, "line " + std::to_string(line_no), "key=value");
    kv.emplace_back(trim(t.substr(0, eq)), trim(t.substr(eq + 1)));
    if (e == text.size()) break;
  }
  return kv;
}

KeyValues read_key_values(const std::string& path) {
  return parse_key_values(read_file(path), path);
}

std::string find_value(const KeyValues& kv, const std::string& key, const std::string& fallback) {
  for (const auto& [k, v] : kv)
    if (k == key) return v;
  return fallback;
}

// ---- stage markers ----

void write_stage_done(const std::string& out, const std::string& design, int stage,
                      const KeyValues& extra) {
  KeyValues kv;
  kv.emplace_back("design", design);
  kv.emplace_back("stage", std::to_string(stage));
  for (const auto& p : extra)
    if (p.first != "design" && p.first != "stage") kv.push_back(p);
  ensure_dir(stages_dir(out));
  write_file_atomic(stage_done_marker(out, design, stage),
                    format_key_values(kv, "millwear stage marker"));
}

int stage_in_file_name(const std::string& name, const std::string& design, const std::string& suffix) {
  const std::string prefix = design + "_stage";
  if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
    return -1;
  int k = -1;
  return parse_int(name.substr(prefix.size(), name.size() - prefix.size() - suffix.size()), &k) ? k : -1;
}

std::vector<int> list_finished_stages(const std::string& out, const std::string& design) {
  std::vector<int> stages;
  std::error_code ec;
  const std::string dir = stages_dir(out);
  if (!fs::is_directory(dir, ec)) return stages;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (!entry.is_regular_file(ec)) continue;
    const int k = stage_in_file_name(entry.path().filename().string(), design, ".done");
    if (k < 0) continue;
    try {
      KeyValues kv = read_key_values(entry.path().string());
      if (find_value(kv, "design") != design) continue;
      if (find_value(kv, "stage") != std::to_string(k)) continue;
    } catch (const InputError&) {
      continue;  // unreadable or garbled marker: the stage is not counted as done
    }
    stages.push_back(k);
  }
  std::sort(stages.begin(), stages.end());
  return stages;
}

int last_finished_stage(const std::string& out, const std::string& design) {
  std::vector<int> done = list_finished_stages(out, design);
  int last = -1;
  for (int k : done) {
    if (k != last + 1) break;
    last = k;
  }
  return last;
}

// ---- the folder's owner ----

std::vector<std::string> manifest_files(const std::string& out) {
  const std::string path = manifest_path(out);
  if (!file_exists(path)) return {};
  std::vector<std::string> files;
  try {
    const Json m = Json::parse(read_file(path));
    if (m.is_object() && m.contains("files") && m["files"].is_array())
      for (const auto& f : m["files"])
        if (f.is_string()) files.push_back(f.get<std::string>());
  } catch (const std::exception&) {
    return {};
  }
  return files;
}

std::string folder_mark_path(const std::string& out) { return join_path(out, ".millwear-results"); }

namespace {

// The mark's command, or "" when there is no mark or it does not read (then the folder's
// files tell).
std::string marked_command(const std::string& out) {
  const std::string path = folder_mark_path(out);
  if (!file_exists(path)) return "";
  try {
    return find_value(read_key_values(path), "command", "");
  } catch (const std::exception&) {
    return "";
  }
}

}  // namespace

std::vector<std::string> visible_entries(const std::string& folder) {
  std::vector<std::string> names;
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    std::string name = it->path().filename().string();
    if (name.rfind('.', 0) != 0) names.push_back(std::move(name));
  }
  std::sort(names.begin(), names.end());
  return names;
}

void mark_folder(const std::string& out, const std::string& command) {
  if (marked_command(out) == command) return;
  write_file_atomic(folder_mark_path(out),
                    format_key_values({{"command", command}}, "millwear: the command whose results this folder holds"));
}

std::string folder_results_command(const std::string& out) {
  const std::string marked = marked_command(out);
  // A mark with nothing visible beside it: a command stopped (killed) before it wrote.
  if (!marked.empty()) return visible_entries(out).empty() ? "" : marked;
  const std::string path = manifest_path(out);
  if (file_exists(path)) {
    try {
      const Json m = Json::parse(read_file(path));
      if (m.is_object() && m.contains("command") && m["command"].is_string()) return m["command"].get<std::string>();
    } catch (const std::exception&) {
    }
    return "run";
  }
  if (file_exists(run_key_path(out))) return "run";
  // Commands that write no manifest (or did not before the mark): a file that is theirs alone.
  for (const auto& [file, command] : {std::pair<const char*, const char*>{"charge_summary.csv", "charge"},
                                      {"screen.key", "screen"},
                                      {"hardness_fit.csv", "hardness"},
                                      {"calibration_result.csv", "calibrate"}})
    if (file_exists(join_path(out, file))) return command;
  return "";
}

void check_folder_not_taken(const std::string& out, const std::string& command) {
  const std::string holds = folder_results_command(out);
  if (holds.empty()) {
    // Hidden files are no command's results: the lock, a killed command's temporaries, a
    // file manager's or NFS's own.
    const std::vector<std::string> found = visible_entries(out);
    if (found.empty()) return;
    throw InputError(out, "-o",
                     "a new or empty folder, or one `millwear " + command + "` wrote: this command writes only "
                     "there, and this folder holds " + found.front() +
                         (found.size() > 1 ? " and " + std::to_string(found.size() - 1) + " more" : std::string()) +
                         ", of no millwear command's results: use another folder");
  }
  if (holds == command) return;
  throw InputError(out, "-o",
                   "a folder that is new or holds results of `millwear " + command + "`, but it holds those of `millwear " +
                       holds + "`, which this command would partly overwrite: use another folder");
}

void check_output_names(const std::string& out, const std::vector<std::string>& files, const std::string& command) {
  std::error_code ec;
  for (const std::string& f : files) {
    // The folders on the way first: OUT/plots a file refuses plots/x.png as that folder.
    const fs::path rel = fs::path(f).lexically_normal();
    fs::path on_the_way;
    for (auto part = rel.begin(); part != rel.end() && std::next(part) != rel.end(); ++part) {
      on_the_way /= *part;
      const std::string dir = join_path(out, on_the_way.string());
      if (fs::exists(fs::symlink_status(dir, ec)) && !fs::is_directory(dir, ec))
        throw InputError(dir, "-o",
                         "a folder, where `millwear " + command + "` writes " + f + ", but a file of that name is "
                         "there: move it, or use another folder");
    }
    const std::string path = join_path(out, f);
    if (fs::is_directory(fs::symlink_status(path, ec)))
      throw InputError(path, "-o",
                       "a file, which `millwear " + command + "` writes there, but a folder of that name is there "
                       "(no file can replace it): move it, or use another folder");
  }
}

void check_inputs_not_among(const std::string& out, const std::vector<std::string>& files,
                            const std::vector<std::string>& inputs, const std::string& command) {
  std::error_code ec;
  for (const std::string& in : inputs) {
    if (!fs::exists(in, ec)) continue;
    for (const std::string& f : files) {
      const std::string path = join_path(out, f);
      if (fs::exists(path, ec) && fs::equivalent(in, path, ec))
        throw InputError(in, "-o",
                         "an input outside the files `millwear " + command + "` writes or deletes, but it is " +
                             path + ", which it would replace before it is done reading: copy it out of " + out +
                             " and give that copy");
    }
  }
}

}  // namespace millwear::io
