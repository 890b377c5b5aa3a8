#include "outcome.hpp"

#include <signal.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>

namespace mutation {

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// The first stderr line that carries a message ("millwear: error: ...", else the first
// non-empty line), shortened for the report.
std::string first_message(const std::string& err) {
  std::istringstream in(err);
  std::string line, first;
  while (std::getline(in, line)) {
    if (line.find("millwear: error:") != std::string::npos || line.find("millwear: run failed:") != std::string::npos)
      return line;
    if (first.empty() && !line.empty()) first = line;
  }
  return first;
}

std::string shorten(std::string s, std::size_t n = 200) {
  for (char& c : s)
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';
  if (s.size() > n) s = s.substr(0, n) + "...";
  return s;
}

// A location as InputError writes it: a dotted key, "line N" or "column NAME".
bool looks_like_location(const std::string& w) {
  if (w.empty()) return false;
  if (w.rfind("line ", 0) == 0) return w.size() > 5 && std::all_of(w.begin() + 5, w.end(), ::isdigit);
  if (w.rfind("column ", 0) == 0) return w.size() > 7 && w.find(' ', 7) == std::string::npos;
  return std::all_of(w.begin(), w.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '[' || c == ']' || c == '-';
  });
}

// The library exceptions that mean a bug let bad input through, not a named run failure.
bool is_library_exception(const std::string& msg) {
  static const char* const kMarks[] = {"std::", "basic_string", "stod", "stoi", "stol", "vector::", "_M_",
                                       "filesystem error", "bad_array_new_length", "map::at", "bad_optional",
                                       "bad_variant", "out_of_range", "invalid_argument", "length_error"};
  for (const char* m : kMarks)
    if (msg.find(m) != std::string::npos) return true;
  return false;
}

bool mentions_alloc(const std::string& err) {
  return err.find("bad_alloc") != std::string::npos || err.find("Cannot allocate memory") != std::string::npos ||
         err.find("out of memory") != std::string::npos;
}

// The one documented not-a-number of the outputs: validate's loss error in % of a measured
// loss of 0 (a survey row at 0 h; study/area_fit.hpp).
bool documented_non_finite(const fs::path& file, const std::vector<std::string>& header,
                           const std::vector<std::string>& fields, std::size_t i) {
  // Label columns copy the user's text ("inf" is a fine period label), they are not numbers.
  static const std::set<std::string> kLabels{"period", "design", "species", "species_name", "scene", "name",
                                             "owner", "quantity", "unit", "status", "reason", "time_unit",
                                             "wear_column", "direction", "profile_source", "scene_file",
                                             "profile_file"};
  if (kLabels.count(header[i])) return true;
  if (file.filename() != "validation.csv" || header[i] != "loss_error_pct") return false;
  for (std::size_t k = 0; k < header.size(); ++k)
    if (header[k] == "measured_loss_mm2") return std::strtod(fields[k].c_str(), nullptr) == 0.0;
  return false;
}

// One CSV file: quoted fields allowed (RFC 4180), '#' comment lines skipped.
std::string check_csv(const fs::path& file, const fs::path& root, std::size_t* data_rows) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str();
  const std::string name = fs::relative(file, root).string();
  std::size_t line = 1, record_line = 1, header_fields = 0, rows = 0;
  bool have_header = false, quoted = false, field_was_quoted = false;
  std::vector<std::string> fields, header;
  std::string field;
  auto finish_field = [&]() {
    fields.push_back(field);
    field.clear();
  };
  auto finish_record = [&]() -> std::string {
    if (fields.size() == 1 && fields[0].empty()) return "";  // blank line
    if (!fields.empty() && !fields[0].empty() && fields[0][0] == '#') return "";
    if (!have_header) {
      have_header = true;
      header_fields = fields.size();
      header = fields;
      return "";
    }
    ++rows;
    if (fields.size() != header_fields)
      return "malformed CSV " + name + " line " + std::to_string(record_line) + ": " +
             std::to_string(fields.size()) + " fields, header has " + std::to_string(header_fields);
    for (std::size_t i = 0; i < fields.size(); ++i) {
      const std::string f = lower(fields[i]);
      std::string t = f;
      t.erase(0, t.find_first_not_of(" \t"));
      if (t.empty()) continue;
      static const std::set<std::string> kNonFinite{"nan", "-nan", "+nan", "inf", "-inf", "+inf", "infinity",
                                                    "-infinity", "+infinity"};
      bool bad = kNonFinite.count(t) > 0;
      if (!bad) {
        char* end = nullptr;
        const double v = std::strtod(t.c_str(), &end);
        if (end != t.c_str() && *end == '\0' && !std::isfinite(v)) bad = true;
      }
      if (bad && !documented_non_finite(file, header, fields, i))
        return "non-finite number in " + name + " line " + std::to_string(record_line) + " field " +
               std::to_string(i + 1) + " (" + header[i] + "): '" + shorten(fields[i], 40) + "'";
    }
    return "";
  };
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (quoted) {
      if (c == '"') {
        if (i + 1 < text.size() && text[i + 1] == '"') {
          field += '"';
          ++i;
        } else {
          quoted = false;
        }
      } else {
        if (c == '\n') ++line;
        field += c;
      }
      continue;
    }
    if (c == '"') {
      if (!field.empty() || field_was_quoted)
        return "malformed CSV " + name + " line " + std::to_string(line) + ": a quote inside an unquoted field";
      quoted = field_was_quoted = true;
    } else if (c == ',') {
      finish_field();
      field_was_quoted = false;
    } else if (c == '\n') {
      finish_field();
      field_was_quoted = false;
      if (!fields.empty() && fields.back().size() && fields.back().back() == '\r') fields.back().pop_back();
      const std::string p = finish_record();
      if (!p.empty()) return p;
      fields.clear();
      ++line;
      record_line = line;
    } else {
      field += c;
    }
  }
  if (quoted) return "malformed CSV " + name + ": a quoted field is never closed";
  if (!field.empty() || !fields.empty()) {
    finish_field();
    const std::string p = finish_record();
    if (!p.empty()) return p;
  }
  if (data_rows) *data_rows = rows;
  return "";
}

}  // namespace

const char* outcome_name(Outcome o) {
  switch (o) {
    case Outcome::Ok: return "ok";
    case Outcome::Refused: return "refused";
    case Outcome::RefusedElsewhere: return "refused-elsewhere";
    case Outcome::Event: return "event";
    case Outcome::Signal: return "signal";
    case Outcome::Hang: return "hang";
    case Outcome::Alloc: return "alloc";
    case Outcome::BadExit: return "bad-exit";
  }
  return "?";
}

bool is_failure(Outcome o) {
  return o == Outcome::Signal || o == Outcome::Hang || o == Outcome::Alloc || o == Outcome::BadExit;
}

std::vector<fs::path> files_under(const fs::path& dir, const fs::path& skip) {
  std::vector<fs::path> out;
  std::error_code ec;
  if (!fs::exists(dir, ec)) return out;
  for (auto it = fs::recursive_directory_iterator(dir, ec); it != fs::recursive_directory_iterator(); it.increment(ec)) {
    if (ec) break;
    if (!skip.empty() && it->path() == skip) {
      it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file(ec) || it->is_symlink(ec)) out.push_back(it->path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::string check_csv_tree(const fs::path& dir) {
  for (const fs::path& f : files_under(dir, {}))
    if (f.extension() == ".csv") {
      const std::string p = check_csv(f, dir, nullptr);
      if (!p.empty()) return p;
    }
  return "";
}

Judged judge(const Step& step, const Finished& run, const Expectation& expect, const fs::path& case_dir,
             const std::vector<fs::path>& files_before) {
  Judged j;
  j.message = shorten(first_message(run.err));
  if (run.timed_out) {
    j.outcome = Outcome::Hang;
    j.detail = "no exit within " + std::to_string(static_cast<int>(step.timeout_s)) + " s";
    return j;
  }
  if (run.signaled) {
    j.outcome = mentions_alloc(run.err) ? Outcome::Alloc : Outcome::Signal;
    j.detail = std::string("killed by signal ") + std::to_string(run.signal) + " (" + strsignal(run.signal) + ")";
    return j;
  }
  if (mentions_alloc(run.err)) {
    j.outcome = Outcome::Alloc;
    j.detail = "exit " + std::to_string(run.exit_code) + " after an allocation failure";
    return j;
  }
  const int code = run.exit_code;
  if (code == 2) {
    // Nothing written: not in the output folder, not beside the inputs.
    std::vector<fs::path> now = files_under(case_dir, case_dir / "log");
    std::vector<fs::path> added;
    std::set_difference(now.begin(), now.end(), files_before.begin(), files_before.end(), std::back_inserter(added));
    if (!added.empty()) {
      j.outcome = Outcome::BadExit;
      j.detail = "exit 2 but wrote " + fs::relative(added.front(), case_dir).string() +
                 (added.size() > 1 ? " and " + std::to_string(added.size() - 1) + " more" : "");
      return j;
    }
    const std::string msg = first_message(run.err);
    // "FILE: WHERE: expected ..." (InputError's format): the location after the file name.
    auto location_after = [&](const std::string& name, std::string* where) {
      // the commands are given absolute paths, so the name follows a '/'
      const std::size_t at = msg.find("/" + name + ": ");
      if (at == std::string::npos) return false;
      const std::size_t from = at + 1 + name.size() + 2;
      const std::size_t to = msg.find(": ", from);
      *where = msg.substr(from, to == std::string::npos ? std::string::npos : to - from);
      return true;
    };
    std::string where;
    if (location_after(expect.file_name, &where) && looks_like_location(where)) {
      const bool exact = std::any_of(expect.locations.begin(), expect.locations.end(), [&](const std::string& l) {
        if (!l.empty() && l.back() == '*') return where.rfind(l.substr(0, l.size() - 1), 0) == 0;
        return l == where;
      });
      const bool line_ok = expect.any_line && where.rfind("line ", 0) == 0;
      j.outcome = exact || line_ok ? Outcome::Refused : Outcome::RefusedElsewhere;
      j.detail = "names " + where;
      return j;
    }
    for (const std::string& other : expect.other_files) {
      std::string w;
      if (location_after(other, &w) && looks_like_location(w)) {
        j.outcome = Outcome::RefusedElsewhere;
        j.detail = "names " + other + ": " + w;
        return j;
      }
    }
    j.outcome = Outcome::BadExit;
    j.detail = msg.find(expect.file_name) != std::string::npos ? "exit 2 naming the file but no key or line"
                                                               : "exit 2 without naming the file";
    return j;
  }
  if (code == 1) {
    const std::string msg = first_message(run.err);
    if (step.validation_only) {
      j.outcome = Outcome::BadExit;
      j.detail = "exit 1 from a validation-only command (bad input is exit 2)";
    } else if (msg.empty()) {
      j.outcome = Outcome::BadExit;
      j.detail = "exit 1 with nothing on stderr";
    } else if (is_library_exception(msg)) {
      j.outcome = Outcome::BadExit;
      j.detail = "exit 1 with a library exception, not a named event";
    } else {
      j.outcome = Outcome::Event;
      j.detail = "exit 1";
    }
    return j;
  }
  if (code == 0 || (code == 130 && step.interrupt_is_success)) {
    // A run that reported non-finite state has no real figures, whatever its exit code says.
    if (run.err.find("non-finite") != std::string::npos) {
      j.outcome = Outcome::BadExit;
      j.detail = "exit " + std::to_string(code) + " although the run reported non-finite state";
      return j;
    }
    const std::string problem = check_csv_tree(step.out_dir);
    if (!problem.empty()) {
      j.outcome = Outcome::BadExit;
      j.detail = "exit " + std::to_string(code) + " with " + problem;
      return j;
    }
    for (const auto& [file, least] : step.required) {
      std::size_t rows = 0;
      const fs::path p = step.out_dir / file;
      std::error_code ec;
      if (!fs::is_regular_file(p, ec)) {
        j.outcome = Outcome::BadExit;
        j.detail = "exit " + std::to_string(code) + " without " + file;
        return j;
      }
      check_csv(p, step.out_dir, &rows);
      if (rows < least) {
        j.outcome = Outcome::BadExit;
        j.detail = "exit " + std::to_string(code) + " with " + std::to_string(rows) + " data rows in " + file;
        return j;
      }
    }
    // A snapshot of the charge with no disk in it is an empty result.
    for (const fs::path& f : files_under(step.out_dir, {})) {
      const std::string n = f.filename().string();
      if (f.extension() != ".csv" || n.rfind("snapshot", 0) != 0) continue;
      std::size_t rows = 0;
      check_csv(f, step.out_dir, &rows);
      if (rows == 0) {
        j.outcome = Outcome::BadExit;
        j.detail = "exit " + std::to_string(code) + " with no disk in " + fs::relative(f, step.out_dir).string();
        return j;
      }
    }
    // The charge summary must describe a charge that ran: disks and simulated time.
    const fs::path summary = step.out_dir / "charge_summary.csv";
    std::error_code ec;
    if (fs::is_regular_file(summary, ec)) {
      std::ifstream in(summary);
      std::string line;
      while (std::getline(in, line)) {
        for (const char* q : {"disks,", "simulated_time,"}) {
          if (line.rfind(q, 0) != 0) continue;
          const double v = std::strtod(line.c_str() + std::strlen(q), nullptr);
          if (!(v > 0.0)) {
            j.outcome = Outcome::BadExit;
            j.detail = "exit 0 with " + std::string(q, std::strlen(q) - 1) + " = " + line.substr(std::strlen(q)) +
                       " in charge_summary.csv";
            return j;
          }
        }
      }
    }
    j.outcome = Outcome::Ok;
    return j;
  }
  j.outcome = Outcome::BadExit;
  j.detail = "exit " + std::to_string(code) + (code == 127 ? " (could not run the program)" : "");
  return j;
}

}  // namespace mutation
