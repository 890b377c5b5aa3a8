#pragma once
// Strict reading of one TOML table (shared by scene files and screen files): every key is
// checked against the table's allowed keys, and an unknown key, a wrong type or an
// out-of-range value throws InputError with the file, the dotted key ("charge.species[1].density"),
// the expectation in the file's units and the line. Internal to the modules that read TOML
// files (scene/, screen/): no toml++ type leaves them.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "common/errors.hpp"
#include "common/text.hpp"

namespace millwear::toml_reader {

inline constexpr double kInf = std::numeric_limits<double>::infinity();

// An interval for a number, with its description for messages ("in (0, 2]", "> 0").
struct Bounds {
  double lo = -kInf, hi = kInf;
  bool lo_open = false, hi_open = false;

  bool contains(double v) const {
    if (lo_open ? !(v > lo) : !(v >= lo)) return false;
    if (hi_open ? !(v < hi) : !(v <= hi)) return false;
    return true;
  }
  std::string describe() const;
};

inline std::string num_text(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

inline std::string Bounds::describe() const {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (has_lo && has_hi)
    return std::string("in ") + (lo_open ? "(" : "[") + num_text(lo) + ", " + num_text(hi) +
           (hi_open ? ")" : "]");
  if (has_lo) return (lo_open ? "> " : ">= ") + num_text(lo);
  if (has_hi) return (hi_open ? "< " : "<= ") + num_text(hi);
  return "";
}

inline Bounds positive() { return {0.0, kInf, true, false}; }
inline Bounds closed(double lo, double hi) { return {lo, hi, false, false}; }
inline Bounds open_closed(double lo, double hi) { return {lo, hi, true, false}; }
inline Bounds open(double lo, double hi) { return {lo, hi, true, true}; }

inline std::string type_name(toml::node_type t) {
  switch (t) {
    case toml::node_type::table: return "a table";
    case toml::node_type::array: return "an array";
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a float";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::date: return "a date";
    case toml::node_type::time: return "a time";
    case toml::node_type::date_time: return "a date-time";
    default: return "nothing";
  }
}

// "got a string 'ten'" / "got -3" / "got an array [0.5, 0.4]"; long values are shortened.
inline std::string value_text(const toml::node& n) {
  if (n.is_integer()) return std::to_string(n.as_integer()->get());
  if (n.is_floating_point()) return num_text(n.as_floating_point()->get());
  if (n.is_boolean()) return n.as_boolean()->get() ? "true" : "false";
  if (n.is_string()) return "'" + printable(n.as_string()->get(), 40) + "'";
  if (n.is_array()) {
    std::string out = "[";
    for (std::size_t i = 0; i < n.as_array()->size(); ++i)
      out += (i ? ", " : "") + value_text((*n.as_array())[i]);
    return out + "]";
  }
  return "";
}

inline std::string got_text(const toml::node& n) {
  std::string v = value_text(n);
  // A float with an integral value (1e3) shown as one, so that "expected an integer ...,
  // got 1000.0" does not read as a contradiction.
  if (n.is_floating_point() && v.find_first_of(".eEinIN") == std::string::npos) v += ".0";
  if (v.size() > 40) v = v.substr(0, 37) + "...";
  if (n.is_number()) return "got " + v;
  return "got " + type_name(n.type()) + (v.empty() ? "" : " " + v);
}

inline std::string line_text(const toml::node& n) {
  const auto line = n.source().begin.line;
  return line > 0 ? " (line " + std::to_string(line) + ")" : "";
}

inline std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

// A key as shown in a message.
inline std::string printable_key(const std::string& key) { return printable(key, 64); }

// One TOML table with a dotted prefix and its list of allowed keys. Every accessor checks
// the type and range and records the key in the scene's explicit keys.
class TableReader {
 public:
  TableReader(const toml::table& table, std::string prefix, const std::string& file,
              std::set<std::string>* explicit_keys, std::vector<std::string> allowed)
      : table_(table), prefix_(std::move(prefix)), file_(file), explicit_(explicit_keys),
        allowed_(std::move(allowed)) {
    for (const auto& [k, v] : table_) {
      const std::string key(k.str());
      if (std::find(allowed_.begin(), allowed_.end(), key) != allowed_.end()) continue;
      std::string expected = "unknown key";
      std::string best;
      std::size_t best_d = 3;  // suggest only near misses (typos)
      for (const auto& a : allowed_) {
        if (key.size() > a.size() + best_d) continue;
        const std::size_t d = edit_distance(key, a);
        if (d < best_d) best_d = d, best = a;
      }
      if (!best.empty()) expected += " (did you mean '" + best + "'?)";
      expected += "; allowed here: ";
      for (std::size_t i = 0; i < allowed_.size(); ++i)
        expected += (i ? ", " : "") + allowed_[i];
      throw InputError(file_, full(printable_key(key)), expected + line_text(v));
    }
  }

  std::string full(const std::string& key) const {
    return prefix_.empty() ? key : prefix_ + "." + key;
  }
  bool has(const char* key) const { return table_.contains(key); }

  [[noreturn]] void fail(const std::string& key, const std::string& expected) const {
    const toml::node* n = table_.get(key);
    if (n) throw InputError(file_, full(key), "expected " + expected + ", " + got_text(*n) + line_text(*n));
    throw InputError(file_, full(key), expected + line_text(table_));
  }
  [[noreturn]] void missing(const std::string& key, const std::string& expected) const {
    throw InputError(file_, full(key), "required key missing: " + expected + line_text(table_));
  }

  // A number (integer or float) within bounds; unit is the file's unit, for messages.
  std::optional<double> number(const char* key, Bounds b, const std::string& unit) const {
    const toml::node* n = get(key);
    if (!n) return std::nullopt;
    const std::string what = "a number" + suffix(b.describe(), unit);
    if (!n->is_number()) fail(key, what);
    const double v = n->is_integer() ? static_cast<double>(n->as_integer()->get())
                                     : n->as_floating_point()->get();
    if (!std::isfinite(v) || !b.contains(v)) fail(key, what);
    return v;
  }
  double need_number(const char* key, Bounds b, const std::string& unit) const {
    if (!has(key)) missing(key, "a number" + suffix(b.describe(), unit));
    return *number(key, b, unit);
  }

  std::optional<long long> integer(const char* key, long long lo, long long hi,
                                   const std::string& unit = "") const {
    const toml::node* n = get(key);
    if (!n) return std::nullopt;
    const std::string what =
        "an integer" + suffix(hi == std::numeric_limits<long long>::max()
                                  ? ">= " + std::to_string(lo)
                                  : "in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]",
                              unit);
    if (!n->is_integer()) fail(key, what);
    const long long v = n->as_integer()->get();
    if (v < lo || v > hi) fail(key, what);
    return v;
  }

  std::optional<bool> boolean(const char* key) const {
    const toml::node* n = get(key);
    if (!n) return std::nullopt;
    if (!n->is_boolean()) fail(key, "true or false");
    return n->as_boolean()->get();
  }

  std::optional<std::string> string(const char* key) const {
    const toml::node* n = get(key);
    if (!n) return std::nullopt;
    if (!n->is_string()) fail(key, "a string");
    return n->as_string()->get();
  }

  // One of a fixed set of words; returns its index.
  std::optional<int> choice(const char* key, const std::vector<std::string>& words) const {
    std::string list;
    for (std::size_t i = 0; i < words.size(); ++i)
      list += (i ? (i + 1 == words.size() ? " or " : ", ") : "") + ("\"" + words[i] + "\"");
    const toml::node* n = get(key);
    if (!n) return std::nullopt;
    if (!n->is_string()) fail(key, list);
    const std::string v = n->as_string()->get();
    for (std::size_t i = 0; i < words.size(); ++i)
      if (v == words[i]) return static_cast<int>(i);
    fail(key, list);
  }

  // An array of numbers, each within bounds (and at least min_len of them).
  std::optional<std::vector<double>> numbers(const char* key, Bounds b, const std::string& unit,
                                             std::size_t min_len) const {
    const toml::node* n = get(key);
    if (!n) return std::nullopt;
    const std::string what = "an array of at least " + std::to_string(min_len) + " number" +
                             (min_len == 1 ? "" : "s") + suffix(b.describe(), unit);
    if (!n->is_array()) fail(key, what);
    const toml::array& arr = *n->as_array();
    if (arr.size() < min_len) fail(key, what);
    std::vector<double> out;
    for (std::size_t i = 0; i < arr.size(); ++i) {
      const toml::node& e = arr[i];
      const std::string ekey = full(key) + "[" + std::to_string(i) + "]";
      const std::string ewhat = "a number" + suffix(b.describe(), unit);
      if (!e.is_number()) throw InputError(file_, ekey, "expected " + ewhat + ", " + got_text(e) + line_text(e));
      const double v = e.is_integer() ? static_cast<double>(e.as_integer()->get())
                                      : e.as_floating_point()->get();
      if (!std::isfinite(v) || !b.contains(v))
        throw InputError(file_, ekey, "expected " + ewhat + ", " + got_text(e) + line_text(e));
      out.push_back(v);
    }
    return out;
  }

  const toml::table* table(const char* key) const {
    const toml::node* n = get(key);
    if (!n) return nullptr;
    if (!n->is_table()) fail(key, "a table [" + full(key) + "]");
    return n->as_table();
  }

  const toml::array* array(const char* key) const {
    const toml::node* n = get(key);
    if (!n) return nullptr;
    if (!n->is_array()) fail(key, "an array of tables [[" + full(key) + "]]");
    return n->as_array();
  }

  const toml::table& raw() const { return table_; }

 private:
  const toml::node* get(const char* key) const {
    const toml::node* n = table_.get(key);
    if (n && explicit_) explicit_->insert(full(key));
    return n;
  }
  static std::string suffix(const std::string& range, const std::string& unit) {
    std::string s;
    if (!range.empty()) s += " " + range;
    if (!unit.empty()) s += " (" + unit + ")";
    return s;
  }

  const toml::table& table_;
  std::string prefix_;
  const std::string& file_;
  std::set<std::string>* explicit_;
  std::vector<std::string> allowed_;
};

}  // namespace millwear::toml_reader
