// A scene file's text with its wear rate replaced (see scene_edit.hpp). toml++ finds where
// each key and value sit (line and column); the text itself is edited, so nothing else of
// the file changes.
#include "scene/scene_edit.hpp"

#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <utility>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <vector>

#include "common/errors.hpp"

namespace millwear {

namespace fs = std::filesystem;

namespace {

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

// Replace columns [from, to) (1-based, to exclusive) of line `line` (1-based).
void replace_span(std::vector<std::string>& lines, std::size_t line, std::size_t from, std::size_t to,
                  const std::string& with, const std::string& path) {
  if (line == 0 || line > lines.size() || from == 0 || to < from || to - 1 > lines[line - 1].size())
    throw RunError("cannot edit " + path + " at line " + std::to_string(line) + " (unexpected layout)");
  lines[line - 1] = lines[line - 1].substr(0, from - 1) + with + lines[line - 1].substr(to - 1);
}

// A path as a TOML string: literal ('...') unless it holds a quote, else a basic string
// with TOML's escapes (the same as JSON's).
std::string toml_path_string(const std::string& p) {
  if (p.find('\'') == std::string::npos) return "'" + p + "'";
  std::string q = "\"";
  for (char c : p) {
    const unsigned char u = static_cast<unsigned char>(c);
    switch (c) {
      case '"': q += "\\\""; break;
      case '\\': q += "\\\\"; break;
      case '\n': q += "\\n"; break;
      case '\r': q += "\\r"; break;
      case '\t': q += "\\t"; break;
      case '\b': q += "\\b"; break;
      case '\f': q += "\\f"; break;
      default:
        if (u < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", u);
          q += buf;
        } else {
          q += c;  // UTF-8 passes through unchanged
        }
    }
  }
  return q + '"';
}


// A line's columns [from, to) replaced with text (1-based, as toml++ gives them).
struct SpanEdit { std::size_t line, from, to; std::string with; };

// The spans applied bottom-up, and right to left within a line, so that each edit's line and
// columns still point where the parse found them.
void apply_spans(std::vector<SpanEdit> spans, std::vector<std::string>& lines, const std::string& scene_path) {
  std::sort(spans.begin(), spans.end(), [](const SpanEdit& a, const SpanEdit& b) {
    return a.line != b.line ? a.line > b.line : a.from > b.from;
  });
  for (const SpanEdit& e : spans) replace_span(lines, e.line, e.from, e.to, e.with, scene_path);
}

// lifters.profile, or each profile of lifters.pattern, rewritten to resolve from out_dir
// (relative when the copy stays near the scene, else absolute); nothing when out_dir is the
// scene's folder or the scene names no profile.
std::vector<SpanEdit> profile_repoint(toml::table& t, const std::string& scene_path, const std::string& out_dir) {
  const fs::path scene_dir = fs::absolute(fs::path(scene_path)).parent_path();
  const fs::path target_dir = fs::absolute(fs::path(out_dir));
  toml::table* lifters = t["lifters"].as_table();
  if (!lifters || fs::weakly_canonical(scene_dir) == fs::weakly_canonical(target_dir)) return {};
  std::vector<std::pair<std::string, toml::node*>> paths;  // key, value
  if (toml::node* prof = lifters->get("profile"); prof && prof->is_string()) paths.push_back({"lifters.profile", prof});
  if (toml::array* pattern = lifters->get_as<toml::array>("pattern"))
    for (std::size_t k = 0; k < pattern->size(); ++k)
      if (toml::node* e = pattern->get(k); e->is_string())
        paths.push_back({"lifters.pattern[" + std::to_string(k) + "]", e});
  std::vector<SpanEdit> spans;
  for (const auto& [key, node] : paths) {
    const fs::path resolved = (scene_dir / fs::path(node->as_string()->get())).lexically_normal();
    std::string rel = fs::relative(resolved, fs::weakly_canonical(target_dir)).string();
    if (rel.rfind("../../", 0) == 0) rel = resolved.string();
    const auto vs = node->source();
    if (vs.begin.line != vs.end.line) throw RunError(scene_path + ": " + key + " spans lines");
    spans.push_back({vs.begin.line, vs.begin.column, vs.end.column, toml_path_string(rel.empty() ? resolved.string() : rel)});
  }
  return spans;
}

// The scene's text parsed, or an InputError naming the file.
toml::table parse_scene_text(const std::string& text, const std::string& scene_path) {
  try {
    return toml::parse(text, scene_path);
  } catch (const toml::parse_error& e) {
    throw InputError(scene_path, "", std::string("a TOML file: ") + e.what());
  }
}

}  // namespace

std::string calibrated_scene_text(const std::string& text, const std::string& scene_path, const WearRateEdit& edit) {
  toml::table t = parse_scene_text(text, scene_path);
  std::vector<std::string> lines = split_lines(text);
  std::vector<SpanEdit> edits;

  toml::table* wear = t["wear"].as_table();
  if (!wear) throw InputError(scene_path, "wear", "a [wear] table with the wear rate to replace");
  bool done = false;
  for (auto&& [k, v] : *wear) {
    const std::string key(k.str());
    if (key != "wear_rate" && key != "area_loss_rate" && key != "height_loss_rate") continue;
    const auto ks = k.source(), vs = v.source();
    if (ks.begin.line != vs.end.line)
      throw RunError(scene_path + ": the wear-rate key and value are not on one line; set wear_rate by hand");
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.6g", edit.wear_rate_m3_per_J);
    // In an inline table other keys may follow on the line: the key and value alone are
    // replaced (the header line carries the note).
    if (wear->is_inline())
      edits.push_back({ks.begin.line, ks.begin.column, vs.end.column, std::string("wear_rate = ") + buf});
    else
      edits.push_back({ks.begin.line, ks.begin.column, lines[vs.end.line - 1].size() + 1,
                       std::string("wear_rate = ") + buf + "   # m^3/J, " + edit.note});
    done = true;
  }
  if (!done)
    throw InputError(scene_path, "wear.wear_rate",
                     "a wear-rate key to replace (wear_rate, area_loss_rate or height_loss_rate)");

  for (SpanEdit& e : profile_repoint(t, scene_path, edit.out_dir)) edits.push_back(std::move(e));
  apply_spans(std::move(edits), lines, scene_path);

  std::string out = std::string(kCalibratedCopyHeader) + " " + scene_path + " written by millwear calibrate (" + edit.note + ").\n";
  for (const auto& l : lines) out += l + "\n";
  return out;
}

std::string toml_string_value(const std::string& s) { return toml_path_string(s); }

std::string edited_scene_text(const std::string& text, const std::string& scene_path,
                              const std::vector<KeyEdit>& key_edits, const std::string& out_dir,
                              const std::string& header) {
  toml::table t = parse_scene_text(text, scene_path);
  std::vector<std::string> lines = split_lines(text);
  std::vector<SpanEdit> spans;                              // within a line
  std::vector<std::pair<std::size_t, std::string>> inserts;  // after a line (0: at the end)
  std::string head;  // top-level keys added before the first table
  bool profile_edited = false;
  for (const KeyEdit& k : key_edits) {
    if (k.table == "lifters" && k.key == "profile") profile_edited = true;
    const bool remove = k.value.empty();
    const bool root = k.table.empty();
    toml::node* node = root ? &t : t.get(k.table);
    if (node && !node->is_table())
      throw RunError(scene_path + ": '" + k.table + "' is not a table; set " + k.table + "." + k.key + " by hand");
    toml::table* table = node ? node->as_table() : nullptr;
    if (!table) {
      if (!remove) inserts.push_back({0, "\n[" + k.table + "]\n" + k.key + " = " + k.value});
      continue;
    }
    if (table->is_inline())
      throw RunError(scene_path + ": [" + k.table + "] is an inline table; set " + k.key + " by hand");
    bool done = false;
    std::size_t last_line = root ? 0 : table->source().begin.line;
    for (auto&& [key, value] : *table) {
      const std::string name(key.str());
      const auto ks = key.source(), vs = value.source();
      if (!value.is_table() && !value.is_array_of_tables()) last_line = std::max<std::size_t>(last_line, vs.end.line);
      const bool match = name == k.key || std::find(k.replaces.begin(), k.replaces.end(), name) != k.replaces.end();
      if (!match) continue;
      if (ks.begin.line != vs.end.line || vs.begin.line == 0)
        throw RunError(scene_path + ": " + k.table + "." + name + " does not sit on one line; set it by hand");
      // A comment after a number was said of its unit or meaning: it stays with an edited value
      // of the same key, and goes with a key removed or replaced by another (an rpm's note is
      // not a fraction's). One after a string or any other value was said of the old choice
      // (the profile a path named), and one that states numbers of its own of the old value
      // ("fraction of critical (41 rpm)"): it goes with the value.
      const std::string& line = lines[vs.end.line - 1];
      const std::string after = vs.end.column - 1 < line.size() ? line.substr(vs.end.column - 1) : "";
      const bool keeps_comment = name == k.key && !remove && value.is_number() &&
                                 std::none_of(after.begin(), after.end(), [](unsigned char c) { return std::isdigit(c); });
      const std::size_t end = keeps_comment ? vs.end.column : lines[vs.end.line - 1].size() + 1;
      spans.push_back({ks.begin.line, ks.begin.column, end, remove ? "" : k.key + " = " + k.value});
      done = true;
    }
    if (done || remove) continue;
    if (last_line == 0) head += k.key + " = " + k.value + "\n";  // a top-level key, none there yet
    else inserts.push_back({last_line, k.key + " = " + k.value});
  }
  if (!profile_edited)
    for (SpanEdit& e : profile_repoint(t, scene_path, out_dir)) spans.push_back(std::move(e));
  apply_spans(std::move(spans), lines, scene_path);
  // Insertions bottom-up, so the line numbers above stay valid; end-of-file ones last.
  std::stable_sort(inserts.begin(), inserts.end(), [](const auto& a, const auto& b) {
    const std::size_t la = a.first ? a.first : SIZE_MAX, lb = b.first ? b.first : SIZE_MAX;
    return la > lb;
  });
  std::string tail;
  for (const auto& [line, with] : inserts) {
    if (line == 0) {
      tail += with + "\n";
      continue;
    }
    if (line > lines.size()) throw RunError("cannot edit " + scene_path + " after line " + std::to_string(line));
    lines.insert(lines.begin() + static_cast<std::ptrdiff_t>(line), with);
  }
  std::string out = header.empty() ? "" : "# " + header + "\n";
  out += head;
  for (const auto& l : lines) out += l + "\n";
  return out + tail;
}

}  // namespace millwear
