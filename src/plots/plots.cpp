#include "plots/plots.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <csignal>
#include <pthread.h>
#include <unistd.h>

#include <gnuplot-iostream.h>

#include "common/errors.hpp"
#include "common/names.hpp"
#include "io/atomic_write.hpp"
#include "io/csv.hpp"
#include "io/run_folder.hpp"

namespace millwear::plots {

namespace fs = std::filesystem;

namespace {

// Single quotes for /bin/sh: 'it'\''s'.
std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') q += "'\\''";
    else q += c;
  }
  return q + "'";
}

// Single-quoted gnuplot string: no escapes are processed inside, a quote is doubled.
std::string gnuplot_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') q += "''";
    else if (c == '\n' || c == '\r') q += ' ';  // a line end would end the command
    else q += c;
  }
  return q + "'";
}

bool valid_gnuplot_name(const std::string& name) {
  if (name.empty() || std::isdigit(static_cast<unsigned char>(name[0]))) return false;
  for (char c : name)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_')) return false;
  return true;
}

std::vector<std::string> split_words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> w;
  for (std::string t; in >> t;) w.push_back(t);
  return w;
}

std::string parent_dir(const std::string& path) {
  fs::path p = fs::path(path).parent_path();
  return p.empty() ? std::string(".") : p.string();
}

// Why drawing may have failed when the cause is the file system, not gnuplot: "; the file
// system holding DIR is full" (less than a megabyte free), else "".
std::string full_disk_hint(const std::string& dir) {
  std::error_code ec;
  const fs::space_info space = fs::space(dir.empty() ? "." : dir, ec);
  // A virtual file system (/proc) reports no capacity at all: not a full disk.
  if (ec || space.capacity == 0 || space.available >= (1u << 20)) return "";
  return "; the file system holding " + dir + " is full (" + std::to_string(space.available / 1024) +
         " kB free)";
}

std::uintmax_t size_or_zero(const std::string& path) {
  std::error_code ec;
  auto n = fs::file_size(path, ec);
  return ec ? 0 : n;
}

// The last few non-empty lines of `text`, joined with " | ", for an error message.
std::string tail_lines(const std::string& text, int count) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    auto b = line.find_first_not_of(" \t\r");
    if (b == std::string::npos) continue;
    lines.push_back(line.substr(b));
  }
  std::string out;
  int start = std::max(0, static_cast<int>(lines.size()) - count);
  for (int i = start; i < static_cast<int>(lines.size()); ++i) {
    if (!out.empty()) out += " | ";
    out += lines[static_cast<std::size_t>(i)];
  }
  return out;
}

// Blocks SIGPIPE in this thread while we write to gnuplot's pipe: if gnuplot dies early,
// the write fails with EPIPE instead of the signal killing the whole program. A SIGPIPE
// raised meanwhile is consumed before the old mask comes back.
class SigpipeGuard {
 public:
  SigpipeGuard() {
    sigemptyset(&pipe_set_);
    sigaddset(&pipe_set_, SIGPIPE);
    sigset_t pending;
    sigemptyset(&pending);
    sigpending(&pending);
    was_pending_ = sigismember(&pending, SIGPIPE) == 1;
    blocked_ = pthread_sigmask(SIG_BLOCK, &pipe_set_, &old_) == 0;
  }
  ~SigpipeGuard() {
    if (!blocked_) return;
    if (!was_pending_) {
      struct timespec zero = {0, 0};
      while (sigtimedwait(&pipe_set_, nullptr, &zero) > 0) {
      }
    }
    pthread_sigmask(SIG_SETMASK, &old_, nullptr);
  }
  SigpipeGuard(const SigpipeGuard&) = delete;
  SigpipeGuard& operator=(const SigpipeGuard&) = delete;

 private:
  sigset_t pipe_set_, old_;
  bool blocked_ = false;
  bool was_pending_ = false;
};

void append_to_log(const std::string& log_path, const std::string& text) {
  if (log_path.empty()) return;
  std::ofstream log(log_path, std::ios::app);
  log << text;
}

std::string now_text() {
  std::time_t t = std::time(nullptr);
  char buf[64];
  std::tm tm{};
  localtime_r(&t, &tm);
  std::strftime(buf, sizeof buf, "%Y-%m-%d %H:%M:%S", &tm);
  return buf;
}

}  // namespace

std::string plots_dir() {
  const char* env = std::getenv("MILLWEAR_PLOTS_DIR");
  if (env && env[0]) {
    const std::string dir = env;
    if (!fs::is_directory(dir))
      throw RunError("MILLWEAR_PLOTS_DIR=" + dir + " is not a folder (it should hold the " +
                     "figure scripts, fig7_area.gp and the others)");
    return dir;
  }
  // Relative to the running executable: an installed one is PREFIX/bin/millwear with the
  // scripts in PREFIX/share/millwear/plots; a built one has share/millwear/plots beside it.
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec || exe.empty())
    throw RunError("figure scripts not found: cannot read /proc/self/exe to locate them; "
                   "set MILLWEAR_PLOTS_DIR to the folder holding fig7_area.gp and the others");
  const fs::path bin = exe.parent_path();
  const std::string candidates[] = {(bin.parent_path() / "share/millwear/plots").string(),
                                    (bin / "share/millwear/plots").string()};
  for (const auto& dir : candidates)
    if (fs::is_directory(dir, ec)) return dir;
  throw RunError("figure scripts not found in " + candidates[0] + " or " + candidates[1] +
                 " (looked relative to " + exe.string() +
                 "); set MILLWEAR_PLOTS_DIR to the folder holding fig7_area.gp and the others");
}

std::string script_path(const std::string& figure) {
  return io::join_path(plots_dir(), figure + ".gp");
}

std::vector<std::string> species_colours(const std::vector<bool>& is_ball) {
  static const char* const kBalls[] = {"#4f6d8f", "#7d9bbd", "#2f4a66", "#9fb6cf"};
  static const char* const kRocks[] = {"#a08c70", "#c2b59b", "#7a6548", "#8f8f7a"};
  std::vector<std::string> out;
  int balls = 0, rocks = 0;
  for (bool b : is_ball) out.push_back(b ? kBalls[balls++ % 4] : kRocks[rocks++ % 4]);
  return out;
}

bool gnuplot_available() {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::string p = path;
  std::size_t start = 0;
  while (start <= p.size()) {
    std::size_t end = p.find(':', start);
    if (end == std::string::npos) end = p.size();
    std::string dir = p.substr(start, end - start);
    if (dir.empty()) dir = ".";
    std::string exe = dir + "/gnuplot";
    if (::access(exe.c_str(), X_OK) == 0 && !fs::is_directory(exe)) return true;
    start = end + 1;
  }
  return false;
}

std::vector<std::string> render_figure(const std::string& script,
                                       const std::map<std::string, std::string>& vars_in,
                                       const std::string& log_path_in) {
  if (!io::file_exists(script))
    throw RunError("gnuplot script not found: " + script +
                   " (set MILLWEAR_PLOTS_DIR to the folder holding the figure scripts)");
  if (!gnuplot_available())
    throw RunError("gnuplot not found on PATH: figures need gnuplot (for example "
                   "`apt-get install gnuplot-nox`); the results themselves are written");

  std::map<std::string, std::string> vars = vars_in;
  for (const auto& kv : vars)
    if (!valid_gnuplot_name(kv.first))
      throw RunError("bad gnuplot variable name '" + kv.first + "' for " + script);
  if (!vars.count("scriptdir")) vars["scriptdir"] = parent_dir(script);

  // Draw to a temporary base next to the final one; rename after checking.
  std::string final_base, temp_base;
  std::vector<std::string> formats = split_words(vars.count("formats") ? vars["formats"] : "png svg");
  auto ob = vars.find("outbase");
  if (ob != vars.end()) {
    final_base = ob->second;
    temp_base = io::temp_path_for(final_base);
    ob->second = temp_base;
  }

  std::string log_path = log_path_in;
  if (log_path.empty() && !final_base.empty())
    log_path = io::join_path(parent_dir(final_base), "gnuplot.log");
  const std::string status_path =
      io::temp_path_for(log_path.empty()
                            ? (fs::temp_directory_path() / "millwear-gnuplot.status").string()
                            : log_path + ".status");
  const std::uintmax_t log_start = log_path.empty() ? 0 : size_or_zero(log_path);
  append_to_log(log_path, "### " + now_text() + " " + script + "\n");

  auto cleanup_temps = [&]() {
    std::error_code ec;
    if (!temp_base.empty())
      for (const auto& f : formats) fs::remove(temp_base + "." + f, ec);
    fs::remove(status_path, ec);
  };

  // The shell runs gnuplot, then records its exit status; the shell itself exits 0, so
  // gnuplot-iostream's pclose has nothing to complain about and we read the real status.
  // Braces send the shell's own messages (e.g. "gnuplot: not found") to the log as well.
  if (!log_path.empty()) io::ensure_dir(parent_dir(log_path));
  // `exit 0` even when the log or the status cannot be written (a full disk): gnuplot-iostream
  // would print its own complaint about pclose; the missing status says it instead, below.
  const std::string cmd = "{ gnuplot >&2; echo $? >" + shell_quote(status_path) + "; } 2>>" +
                          shell_quote(log_path.empty() ? "/dev/null" : log_path) + "; exit 0";
  try {
    SigpipeGuard guard;
    Gnuplot gp(cmd);
    for (const auto& kv : vars) gp << kv.first << " = " << gnuplot_quote(kv.second) << "\n";
    gp << "load " << gnuplot_quote(script) << "\n";
    gp << "exit\n";
    gp.flush();
  } catch (const std::exception& e) {  // pipe could not be opened or written
    cleanup_temps();
    throw RunError("cannot run gnuplot for " + script + ": " + e.what() +
                   full_disk_hint(parent_dir(final_base.empty() ? log_path : final_base)));
  }

  std::string status_text;
  try {
    status_text = io::read_file(status_path);
  } catch (const InputError&) {
    cleanup_temps();
    throw RunError("gnuplot did not finish for " + script + " (no exit status recorded)" +
                   full_disk_hint(parent_dir(final_base.empty() ? log_path : final_base)));
  }
  int status = std::atoi(status_text.c_str());
  if (status != 0) {
    std::string log_tail;
    if (!log_path.empty()) {
      try {
        std::string log = io::read_file(log_path);
        log_tail = tail_lines(log.substr(std::min<std::size_t>(log.size(), log_start)), 4);
      } catch (const InputError&) {
      }
    }
    cleanup_temps();
    if (status == 127)
      throw RunError("gnuplot could not be started for " + script + " (not found or not executable)");
    throw RunError("gnuplot failed on " + script + " (exit status " + std::to_string(status) + ")" +
                   (log_tail.empty() ? "" : ": " + log_tail) +
                   (log_path.empty() ? "" : "; see " + log_path) +
                   full_disk_hint(parent_dir(final_base.empty() ? log_path : final_base)));
  }

  std::vector<std::string> written;
  if (!final_base.empty()) {
    for (const auto& f : formats) {
      const std::string tmp = temp_base + "." + f;
      if (size_or_zero(tmp) == 0) {
        cleanup_temps();
        throw RunError("gnuplot script " + script + " did not write " + final_base + "." + f +
                       (log_path.empty() ? "" : "; see " + log_path) + full_disk_hint(parent_dir(final_base)));
      }
    }
    for (const auto& f : formats) {
      const std::string tmp = temp_base + "." + f, dst = final_base + "." + f;
      if (std::rename(tmp.c_str(), dst.c_str()) != 0) {
        int err = errno;
        cleanup_temps();
        throw RunError("cannot move figure into place: " + dst + " (" + std::strerror(err) + ")");
      }
      written.push_back(dst);
    }
  }
  std::error_code ec;
  fs::remove(status_path, ec);
  return written;
}

// ---- render_all_figures ----

namespace {

struct SplitTable {
  std::vector<std::string> header;
  std::map<std::string, std::vector<std::vector<std::string>>> rows;  // by design
  std::vector<std::string> order;                                     // first appearance
};

SplitTable split_by_design(const io::CsvData& data) {
  SplitTable t;
  t.header = data.header;
  std::size_t dc = data.column("design");
  for (const auto& row : data.rows) {
    const std::string& d = row[dc];
    if (!t.rows.count(d)) t.order.push_back(d);
    t.rows[d].push_back(row);
  }
  return t;
}

void write_rows(const std::string& path, const std::vector<std::string>& header,
                const std::vector<std::vector<std::string>>& rows) {
  io::CsvTable table(header);
  for (const auto& r : rows) table.add_row(std::vector<io::CsvCell>(r.begin(), r.end()));
  table.write(path);
}

std::string join_words(const std::vector<std::string>& w) {
  std::string s;
  for (const auto& x : w) s += (s.empty() ? "" : " ") + x;
  return s;
}

// Stage numbers K with OUT/profiles/DESIGN_stageK.csv, ascending.
std::vector<int> profile_stages(const std::string& out, const std::string& design) {
  std::vector<int> k;
  std::error_code ec;
  const std::string dir = io::profiles_dir(out);
  if (!fs::is_directory(dir, ec)) return k;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const int stage = io::stage_in_file_name(e.path().filename().string(), design, ".csv");
    if (stage >= 0) k.push_back(stage);
  }
  std::sort(k.begin(), k.end());
  return k;
}

std::string hours_text(double h) {
  std::ostringstream s;
  s << std::round(h);
  return s.str();
}

}  // namespace

std::vector<std::string> figure_data_files(const std::string& out, const std::vector<std::string>& designs) {
  std::vector<std::string> files;
  const std::string log_path = io::join_path(io::plots_out_dir(out), "gnuplot.log");
  if (io::file_exists(log_path)) files.push_back(log_path);
  for (const auto& d : designs)
    for (const char* suffix : {"_summary.csv", "_spectrum.csv", "_profiles.dat"}) {
      const std::string f = io::join_path(io::plots_data_dir(out), d + suffix);
      if (io::file_exists(f)) files.push_back(f);
    }
  // A pattern's kinds (kinds_area figure): DESIGN_kind0.csv, DESIGN_kind1.csv, ...
  for (const auto& d : designs)
    for (int k = 0;; ++k) {
      const std::string f = io::join_path(io::plots_data_dir(out), d + "_kind" + std::to_string(k) + ".csv");
      if (!io::file_exists(f)) break;
      files.push_back(f);
    }
  return files;
}

namespace {

// What a snapshot figure needs from OUT/snapshot_DESIGN.csv and OUT/liner_DESIGN.csv: the
// colour column's finite values, and gnuplot variables naming the species and the marks.
struct SnapshotInputs {
  std::string design;
  bool drawable = false;
  std::vector<double> values;
  std::map<std::string, std::string> vars;
};

// Labels may not carry gnuplot's quote or the word separator.
std::string label_word(std::string s) {
  for (char& c : s)
    if (c == ' ' || c == '\'' || c == '"' || c == '\\') c = '_';
  return s.empty() ? "?" : s;
}

SnapshotInputs read_snapshot_inputs(const std::string& out, const std::string& d) {
  SnapshotInputs in;
  in.design = d;
  io::CsvData liner = io::read_csv(io::liner_path(out, d));
  io::CsvData snap = io::read_csv(io::snapshot_path(out, d));
  const std::vector<double> species = snap.numbers("species");
  for (const char* c : {"x_m", "y_m", "radius_m"}) snap.numbers(c);
  // The liner's colour: the wear rate of a run's stage, the shear power of a charge.
  const bool wear = liner.has_column("wear_rate_mm_per_1000h");
  const std::string column = wear ? "wear_rate_mm_per_1000h" : "shear_power_W_per_m2";
  in.vars["lvalue"] = column;
  in.vars["cblabel"] = wear ? "Liner wear rate (mm per 1000 h)" : "Liner shear power (W/m^2)";
  for (double w : liner.numbers(column))
    if (std::isfinite(w)) in.values.push_back(w);
  // Species by index: their names and whether they are balls, for colours and the legend.
  std::map<int, std::pair<std::string, int>> kinds;
  const bool named = snap.has_column("species_name"), balls = snap.has_column("ball");
  for (std::size_t r = 0; r < snap.row_count(); ++r) {
    const int k = static_cast<int>(species[r]);
    if (k < 0 || k > 255 || kinds.count(k)) continue;
    kinds[k] = {named ? snap.rows[r][snap.column("species_name")] : "species " + std::to_string(k),
                balls ? static_cast<int>(snap.number(r, snap.column("ball"))) : 0};
  }
  if (!kinds.empty()) {
    std::string names, colours;
    std::vector<bool> balls;
    for (int k = 0; k <= kinds.rbegin()->first; ++k) {
      const auto it = kinds.find(k);
      names += (k ? " " : "") + (it == kinds.end() ? std::string("-") : label_word(it->second.first));
      balls.push_back(it != kinds.end() && it->second.second == 1);
    }
    for (const std::string& c : species_colours(balls)) colours += (colours.empty() ? "" : " ") + c;
    in.vars["species_names"] = names;
    in.vars["species_colours"] = colours;
  }
  // The marks: the first row carries the stage's toe, shoulder, centre of mass and sense.
  if (liner.row_count() > 0 && liner.has_column("turning")) {
    for (const char* c : {"toe_deg", "shoulder_deg", "centrifuged", "com_x_m", "com_y_m", "turning"})
      in.vars[c] = io::format_number(liner.number(0, liner.column(c)), 8);
  }
  in.drawable = liner.row_count() > 0 && snap.row_count() > 0;
  return in;
}

// The value below which `share` of the values lie (linear between order statistics); 0 for none.
double upper_percentile(std::vector<double> v, double share) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const double pos = share * static_cast<double>(v.size() - 1);
  const auto lo = static_cast<std::size_t>(pos);
  const std::size_t hi = std::min(lo + 1, v.size() - 1);
  return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

}  // namespace

std::vector<std::string> figures_or_throw(const FigureOutcome& outcome) {
  if (outcome.failures.empty()) return outcome.written;
  std::string msg = "some figures failed (" + std::to_string(outcome.written.size()) + " files written):";
  for (const auto& f : outcome.failures) msg += "\n  " + f;
  throw RunError(msg);
}

std::vector<std::string> render_all_figures(const std::string& out, const std::vector<std::string>& designs,
                                            const std::string& reference) {
  return figures_or_throw(draw_all_figures(out, designs, reference));
}

FigureOutcome draw_all_figures(const std::string& out, const std::vector<std::string>& designs_in,
                               const std::string& reference_in) {
  const std::string plots_out = io::plots_out_dir(out), data_dir = io::plots_data_dir(out);
  const std::string log_path = io::join_path(plots_out, "gnuplot.log");
  io::ensure_dir(plots_out);
  io::ensure_dir(data_dir);

  // summary.csv -> DESIGN_summary.csv, sorted by hours.
  std::vector<std::string> designs = designs_in;
  std::set<std::string> with_summary, with_spectrum, with_profiles;
  std::map<std::string, std::map<int, double>> stage_hours;  // design -> stage -> hours
  std::string reference = reference_in;
  const std::string summary = io::summary_path(out);
  if (io::file_exists(summary)) {
    io::CsvData data = io::read_csv(summary);
    SplitTable t = split_by_design(data);
    const std::size_t hc = data.column("hours"), sc = data.column("stage");
    std::size_t pc = data.has_column("power_norm") ? data.column("power_norm") : data.header.size();
    if (designs.empty()) designs = t.order;
    for (auto& [d, rows] : t.rows) {
      // Sort by hours (numbers checked with their line numbers first).
      std::vector<std::pair<double, std::size_t>> key;
      for (std::size_t r = 0; r < data.rows.size(); ++r) {
        if (data.rows[r][data.column("design")] != d) continue;
        double h = data.number(r, hc);
        int k = static_cast<int>(std::lround(data.number(r, sc)));
        stage_hours[d][k] = h;
        if (reference.empty() && k == 0 && pc < data.header.size() &&
            std::fabs(data.number(r, pc) - 1.0) < 1e-6)
          reference = d;
        key.emplace_back(h, key.size());
      }
      std::stable_sort(key.begin(), key.end());
      std::vector<std::vector<std::string>> sorted;
      for (const auto& k : key) sorted.push_back(rows[k.second]);
      if (!io::is_valid_design_name(d)) continue;
      write_rows(io::join_path(data_dir, d + "_summary.csv"), t.header, sorted);
      with_summary.insert(d);
    }
  }

  // spectrum.csv -> DESIGN_spectrum.csv.
  const std::string spectrum = io::spectrum_path(out);
  if (io::file_exists(spectrum)) {
    io::CsvData data = io::read_csv(spectrum);
    SplitTable t = split_by_design(data);
    for (const char* c : {"energy_J_lower", "energy_J_upper", "count_per_s", "energy_W"})
      data.numbers(c);  // checks every value is a number, naming the line if not
    if (designs.empty()) designs = t.order;
    for (const auto& [d, rows] : t.rows) {
      // Only the designs drawn: a run's spectrum.csv also holds each replicate's histogram.
      if (!io::is_valid_design_name(d) || std::find(designs.begin(), designs.end(), d) == designs.end()) continue;
      write_rows(io::join_path(data_dir, d + "_spectrum.csv"), t.header, rows);
      // A charge without a collision (a single disk) has no spectrum to draw on log axes.
      const std::size_t count = data.column("count_per_s");
      const bool any = std::any_of(rows.begin(), rows.end(), [count](const std::vector<std::string>& r) {
        return count < r.size() && std::strtod(r[count].c_str(), nullptr) > 0.0;
      });
      if (any) with_spectrum.insert(d);
    }
  }

  // Without a summary or spectrum, the designs come from the profile file names.
  if (designs.empty()) {
    std::error_code ec;
    std::set<std::string> found;
    if (fs::is_directory(io::profiles_dir(out), ec))
      for (const auto& e : fs::directory_iterator(io::profiles_dir(out), ec)) {
        std::string n = e.path().filename().string();
        auto pos = n.rfind("_stage");
        if (pos != std::string::npos && pos > 0) found.insert(n.substr(0, pos));
      }
    designs.assign(found.begin(), found.end());
  }
  for (const auto& d : designs)
    if (!io::is_valid_design_name(d))
      throw RunError("design name '" + d + "' cannot be used in file names (" + safe_name_rule() + ")");
  if (reference.empty() && !designs.empty()) reference = designs.front();

  // profiles/DESIGN_stageK.csv -> DESIGN_profiles.dat, one titled block per stage.
  for (const auto& d : designs) {
    std::vector<int> stages = profile_stages(out, d);
    if (stages.empty()) continue;
    std::string text;
    for (std::size_t i = 0; i < stages.size(); ++i) {
      const int k = stages[i];
      io::CsvData p = io::read_csv(io::profile_path(out, d, k));
      std::vector<double> x = p.numbers("x_mm"), y = p.numbers("y_mm");
      if (x.empty()) throw InputError(p.path, "line 2", "at least one x_mm,y_mm row");
      std::string title = (k == 0) ? "new" : "stage " + std::to_string(k);
      auto hd = stage_hours.find(d);
      if (hd != stage_hours.end() && hd->second.count(k))
        title += " (" + hours_text(hd->second.at(k)) + " h)";
      if (i) text += "\n\n";
      text += title + ",-\n";
      for (std::size_t j = 0; j < x.size(); ++j)
        text += io::format_number(x[j]) + "," + io::format_number(y[j]) + "\n";
    }
    io::write_file_atomic(io::join_path(data_dir, d + "_profiles.dat"), text);
    with_profiles.insert(d);
  }

  auto subset = [&](const std::set<std::string>& have) {
    std::vector<std::string> s;
    for (const auto& d : designs)
      if (have.count(d)) s.push_back(d);
    return s;
  };

  std::vector<std::string> written, failures;
  auto draw = [&](const std::string& figure, std::map<std::string, std::string> vars,
                  const std::string& name) {
    vars["datadir"] = out;
    vars["outbase"] = io::join_path(plots_out, name);
    vars["reference"] = reference;
    try {
      auto files = render_figure(script_path(figure), vars, log_path);
      written.insert(written.end(), files.begin(), files.end());
    } catch (const RunError& e) {
      failures.push_back(name + ": " + e.what());
    }
  };

  if (auto s = subset(with_profiles); !s.empty())
    draw("fig6_profiles", {{"designs", join_words(s)}}, "fig6_profiles");
  if (auto s = subset(with_summary); !s.empty()) {
    for (const char* fig : {"fig7_area", "fig8_power", "fig9_collision", "fig10_utilization"})
      draw(fig, {{"designs", join_words(s)}}, fig);
  }
  if (auto s = subset(with_spectrum); !s.empty())
    draw("spectrum", {{"designs", join_words(s)}}, "spectrum");

  // kinds.csv (a pattern of lifters) -> DESIGN_kindK.csv, one curve per design and kind.
  const std::string kinds = io::join_path(out, "kinds.csv");
  if (io::file_exists(kinds)) {
    io::CsvData data = io::read_csv(kinds);
    const std::size_t dc = data.column("design"), kc = data.column("kind"), hc = data.column("hours");
    for (const char* c : {"hours", "area_mm2", "area_loss_rate_mm2_per_1000h"}) data.numbers(c);
    std::map<std::string, std::vector<std::pair<double, std::size_t>>> rows;  // series -> (hours, row)
    std::vector<std::string> series;
    for (std::size_t r = 0; r < data.row_count(); ++r) {
      const std::string& d = data.rows[r][dc];
      if (!io::is_valid_design_name(d)) continue;
      const std::string s = d + "_kind" + std::to_string(std::lround(data.number(r, kc)));
      if (!rows.count(s)) series.push_back(s);
      rows[s].emplace_back(data.number(r, hc), r);
    }
    for (auto& [s, key] : rows) {
      std::stable_sort(key.begin(), key.end());
      std::vector<std::vector<std::string>> sorted;
      for (const auto& k : key) sorted.push_back(data.rows[k.second]);
      write_rows(io::join_path(data_dir, s + ".csv"), data.header, sorted);
    }
    // Each curve's title: the design, the kind's profile and its life (* extrapolated).
    std::map<std::string, std::string> vars{{"series", join_words(series)}};
    const bool has_life = data.has_column("life_h") && data.has_column("profile");
    for (std::size_t i = 0; i < series.size() && has_life; ++i) {
      const std::size_t r = rows[series[i]].front().second;
      const double life = data.number(r, "life_h");
      const bool extrapolated = data.has_column("life_extrapolated") && data.number(r, "life_extrapolated") != 0.0;
      char buf[64] = "no life (no wear trend)";
      if (std::isfinite(life)) std::snprintf(buf, sizeof buf, "life %.0f h%s", life, extrapolated ? "*" : "");
      vars["title" + std::to_string(i + 1)] =
          data.rows[r][dc] + " " + data.rows[r][data.column("profile")] + ": " + buf;
    }
    if (!series.empty()) draw("kinds_area", vars, "kinds_area");
  }

  // Snapshots share one colour scale so designs compare by colour. The scale ends at the 95th
  // percentile of every design's edges, not at the largest: a few edges at a lifter's corner
  // take many times the typical rate and would leave the rest of the liner at the bottom
  // colour. Edges above it are drawn in the top colour.
  std::vector<SnapshotInputs> snaps;
  std::vector<double> values;
  for (const auto& d : designs) {
    if (!io::file_exists(io::snapshot_path(out, d)) || !io::file_exists(io::liner_path(out, d)))
      continue;
    SnapshotInputs in = read_snapshot_inputs(out, d);
    if (!in.drawable) continue;
    values.insert(values.end(), in.values.begin(), in.values.end());
    snaps.push_back(std::move(in));
  }
  const double cbmax = upper_percentile(values, 0.95);
  for (const auto& in : snaps) {
    std::map<std::string, std::string> vars = in.vars;
    vars["design"] = in.design;
    vars["designs"] = join_words(designs);
    if (cbmax > 0) vars["cbmax"] = io::format_number(cbmax, 6);
    draw("snapshot", vars, "snapshot_" + in.design);
  }

  return {written, failures};
}

}  // namespace millwear::plots
