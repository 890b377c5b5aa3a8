#include "cases.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

namespace mutation {

namespace {

// Long strings and arrays: big enough to show quadratic or unbounded behaviour, small
// enough that a sound program refuses them in well under a second.
constexpr std::size_t kLongString = 1u << 20;          // 1 MB
constexpr std::size_t kHugeString = 100u << 20;        // 100 MB, for names only
constexpr std::size_t kLongArray = 10000;
constexpr std::size_t kManySizes = 1000;
constexpr std::size_t kManyRows = 100000;
constexpr std::int64_t kHugeInteger = std::int64_t(1) << 62;
const char* const kUnknownKey = "mutation_unknown_key";
const char* const kLongPlaceholder = "MUTATIONLONGSTRINGPLACEHOLDER";

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

void write_text(const fs::path& p, const std::string& s) {
  std::ofstream out(p, std::ios::binary);
  out << s;
  if (!out) throw std::runtime_error("cannot write " + p.string());
}

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    lines.push_back(text.substr(pos, end - pos));
    pos = end + 1;
  }
  return lines;
}

std::vector<std::string> split_fields(const std::string& line) {
  std::vector<std::string> f;
  std::size_t pos = 0;
  for (;;) {
    const std::size_t c = line.find(',', pos);
    f.push_back(line.substr(pos, c == std::string::npos ? std::string::npos : c - pos));
    if (c == std::string::npos) break;
    pos = c + 1;
  }
  return f;
}

std::string join_fields(const std::vector<std::string>& f) {
  std::string s;
  for (std::size_t i = 0; i < f.size(); ++i) s += (i ? "," : "") + f[i];
  return s;
}

bool is_toml_path(const std::string& s) { return s.size() > 5 && s.compare(s.size() - 5, 5, ".toml") == 0; }

// The node at the first n steps of a path (nullptr if the path does not exist).
toml::node* node_at(toml::table& root, const Path& p, std::size_t n) {
  toml::node* cur = &root;
  for (std::size_t i = 0; i < n && cur; ++i) {
    if (p[i].index >= 0) {
      toml::array* a = cur->as_array();
      cur = a && static_cast<std::size_t>(p[i].index) < a->size() ? a->get(static_cast<std::size_t>(p[i].index)) : nullptr;
    } else {
      toml::table* t = cur->as_table();
      cur = t ? t->get(p[i].key) : nullptr;
    }
  }
  return cur;
}

// Puts a value at the path's last step (replacing what is there).
template <typename V>
void put(toml::table& root, const Path& p, V&& v) {
  toml::node* parent = node_at(root, p, p.size() - 1);
  if (!parent) throw std::runtime_error("no parent for " + path_text(p));
  const PathStep& last = p.back();
  if (last.index >= 0) {
    toml::array* a = parent->as_array();
    a->replace(a->cbegin() + last.index, std::forward<V>(v));
  } else {
    parent->as_table()->insert_or_assign(last.key, std::forward<V>(v));
  }
}

void apply_toml_edit(toml::table& root, const Edit& e) {
  const Path& p = e.path;
  switch (e.op) {
    case Op::Remove: {
      toml::node* parent = node_at(root, p, p.size() - 1);
      if (p.back().index >= 0) {
        toml::array* a = parent->as_array();
        a->erase(a->cbegin() + p.back().index);
      } else {
        parent->as_table()->erase(p.back().key);
      }
      return;
    }
    case Op::SetString: put(root, p, e.text); return;
    case Op::SetInteger: put(root, p, e.integer); return;
    case Op::SetFloat: put(root, p, e.number); return;
    case Op::SetBool: put(root, p, e.boolean); return;
    case Op::SetEmptyTable: {
      toml::table t;
      t.is_inline(true);
      put(root, p, std::move(t));
      return;
    }
    case Op::SetEmptyArray: put(root, p, toml::array{}); return;
    case Op::WrapInArray: {
      toml::array a;
      a.push_back(*node_at(root, p, p.size()));
      put(root, p, std::move(a));
      return;
    }
    case Op::LongArray: {
      const toml::array original = *node_at(root, p, p.size())->as_array();
      toml::array a;
      for (std::size_t i = 0; i < e.count; ++i) a.push_back(original[i % original.size()]);
      put(root, p, std::move(a));
      return;
    }
    case Op::AddUnknownKey: {
      toml::node* t = node_at(root, p, p.size());
      t->as_table()->insert_or_assign(kUnknownKey, 1);
      return;
    }
    case Op::LongString: put(root, p, std::string(kLongPlaceholder)); return;
    case Op::ManySizes: {
      // sizes spread over [0.8 min, max] of the original sizes, fractions 1/count each
      const toml::array original = *node_at(root, p, p.size())->as_array();
      double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
      for (const auto& n : original) {
        const double v = n.value<double>().value_or(1.0);
        lo = std::min(lo, v), hi = std::max(hi, v);
      }
      lo *= 0.8;
      toml::array sizes, fractions;
      for (std::size_t i = 0; i < e.count; ++i) {
        sizes.push_back(lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(e.count - 1));
        fractions.push_back(1.0 / static_cast<double>(e.count));
      }
      put(root, p, std::move(sizes));
      Path fp = p;
      fp.back().key = "mass_fractions";
      put(root, fp, std::move(fractions));
      return;
    }
    case Op::EmptyTable: {
      toml::table* t = node_at(root, p, p.size())->as_table();
      t->clear();
      return;
    }
    default: throw std::runtime_error("not a TOML edit");
  }
}

// Writes a TOML document, expanding the long-string placeholder to `long_len` characters
// without holding them in memory.
void write_toml(const fs::path& file, const toml::table& root, std::size_t long_len) {
  std::ostringstream os;
  os << root << "\n";
  const std::string text = os.str();
  std::ofstream out(file, std::ios::binary);
  const std::size_t at = text.find(kLongPlaceholder);
  if (at == std::string::npos || long_len == 0) {
    out << text;
  } else {
    out << text.substr(0, at);
    const std::string chunk(1 << 16, 'x');
    for (std::size_t left = long_len; left > 0;) {
      const std::size_t n = std::min(left, chunk.size());
      out.write(chunk.data(), static_cast<std::streamsize>(n));
      left -= n;
    }
    out << text.substr(at + std::string(kLongPlaceholder).size());
  }
  if (!out) throw std::runtime_error("cannot write " + file.string());
}

// ------------------------------------------------------------------------------------------
// The hostile values
// ------------------------------------------------------------------------------------------

struct Builder {
  const Source& source;
  std::vector<Case>& out;

  // container: the edited node is a table or an array, so a refusal naming any key inside
  // it names the edit ("lifters" emptied -> "lifters.rows: required key missing").
  bool container = false;

  void add(const Path& p, const std::string& cls, Edit e, std::vector<std::string> where = {}) {
    Case c;
    c.source = &source;
    c.key = path_text(p);
    c.value_class = cls;
    e.path = p;
    c.edit = std::move(e);
    if (where.empty()) {
      // the key itself, or (for an element of an array of values) the array's key
      std::string k = c.key;
      where.push_back(k);
      while (!k.empty() && k.back() == ']') {
        k = k.substr(0, k.rfind('['));
        where.push_back(k);
      }
    }
    if (container && !c.key.empty()) {
      c.locations.push_back(c.key + ".*");
      c.locations.push_back(c.key + "[*");
    }
    for (auto& w : where) c.locations.push_back(std::move(w));
    out.push_back(std::move(c));
  }
  static Edit op(Op o) { Edit e; e.op = o; return e; }
  static Edit str(const std::string& s) { Edit e; e.op = Op::SetString; e.text = s; return e; }
  static Edit integer(std::int64_t v) { Edit e; e.op = Op::SetInteger; e.integer = v; return e; }
  static Edit number(double v) { Edit e; e.op = Op::SetFloat; e.number = v; return e; }
  static Edit boolean(bool v) { Edit e; e.op = Op::SetBool; e.boolean = v; return e; }
  static Edit long_string(std::size_t n) { Edit e; e.op = Op::LongString; e.count = n; return e; }

  void wrong_types(const Path& p, const toml::node& n) {
    if (!n.is_string()) add(p, "type-string", str("ten"));
    if (!n.is_number()) add(p, "type-number", integer(1));
    if (!n.is_table()) add(p, "type-table", op(Op::SetEmptyTable));
    if (!n.is_array()) add(p, "type-array", op(Op::WrapInArray));
    if (!n.is_boolean()) add(p, "type-bool", boolean(true));
  }

  void numbers(const Path& p, double original, bool integer_key) {
    if (integer_key) add(p, "type-float", number(1.5));
    add(p, "nan", number(std::numeric_limits<double>::quiet_NaN()));
    add(p, "inf", number(std::numeric_limits<double>::infinity()));
    add(p, "-inf", number(-std::numeric_limits<double>::infinity()));
    const double neg = original != 0.0 ? -std::abs(original) : -1.0;
    if (integer_key) {
      add(p, "negative", integer(static_cast<std::int64_t>(neg)));
      add(p, "zero", integer(0));
      add(p, "huge-int", integer(kHugeInteger));
      add(p, "-huge-int", integer(-kHugeInteger));
    } else {
      add(p, "negative", number(neg));
      add(p, "zero", number(0.0));
    }
    add(p, "huge", number(1e300));
    add(p, "tiny", number(1e-300));
  }

  void strings(const Path& p, const std::string& original) {
    const std::string leaf = p.back().index >= 0 ? "" : p.back().key;
    add(p, "empty-string", str(""));
    add(p, "long-string", long_string(kLongString));
    if (leaf == "name") add(p, "huge-string", long_string(kHugeString));
    add(p, "control-chars", str("a\x01\x07\x1b[2Jb\x7f"));
    add(p, "nul", str(std::string("a\0b", 3)));
    add(p, "newline", str("a\nb"));
    add(p, "comma", str("a,b"));
    add(p, "quote", str("a\"b"));
    add(p, "path-chars", str("../a/b"));
    if (is_toml_path(original)) {
      add(p, "dir-path", str("."));
      add(p, "self-path", str(source.path.filename().string()));
      add(p, "missing-file", str("no-such-file.toml"));
    }
  }

  void value(const Path& p, const toml::node& n) {
    container = n.is_table() || n.is_array();
    add(p, "absent", op(Op::Remove));
    wrong_types(p, n);
    if (n.is_floating_point()) numbers(p, n.as_floating_point()->get(), false);
    else if (n.is_integer()) numbers(p, static_cast<double>(n.as_integer()->get()), true);
    else if (n.is_string()) strings(p, n.as_string()->get());
    else if (n.is_array() && !n.as_array()->empty()) {
      add(p, "empty-array", op(Op::SetEmptyArray));
      Edit e = op(Op::LongArray);
      e.count = kLongArray;
      add(p, "long-array", e);
    } else if (n.is_table()) {
      add(p, "empty-table", op(Op::EmptyTable));
    }
    if (n.is_table()) {
      Path k = p;
      k.push_back({kUnknownKey, -1});
      container = false;
      add(p, "unknown-key", op(Op::AddUnknownKey), {path_text(k)});
    }
    container = false;
  }

  void walk(const toml::node& n, const Path& p) {
    if (const toml::table* t = n.as_table()) {
      for (auto&& [k, v] : *t) {
        Path c = p;
        c.push_back({std::string(k.str()), -1});
        value(c, v);
        if (k.str() == "sizes" && v.is_array() && t->contains("mass_fractions")) {
          Edit e = op(Op::ManySizes);
          e.count = kManySizes;
          Path f = p;
          f.push_back({"mass_fractions", -1});
          add(c, "many-sizes", e, {path_text(c), path_text(f)});
        }
        walk(v, c);
      }
    } else if (const toml::array* a = n.as_array()) {
      for (std::size_t i = 0; i < a->size(); ++i) {
        Path c = p;
        c.push_back({"", static_cast<long>(i)});
        value(c, (*a)[i]);
        walk((*a)[i], c);
      }
    }
  }
};

// CSV: each column, at the first, a middle and the last data row, and the file's shape.
void csv_cases(const Source& s, std::vector<Case>& out) {
  const std::vector<std::string> header = split_fields(s.lines[s.header_index]);
  std::vector<std::size_t> data;
  for (std::size_t i = s.header_index + 1; i < s.lines.size(); ++i)
    if (!s.lines[i].empty() && s.lines[i][0] != '#') data.push_back(i);
  if (data.empty()) return;
  auto add = [&](const std::string& key, const std::string& cls, Edit e, std::vector<std::string> where,
                 bool any_line) {
    Case c;
    c.source = &s;
    c.key = key;
    c.value_class = cls;
    c.edit = std::move(e);
    c.locations = std::move(where);
    c.any_line = any_line;
    out.push_back(std::move(c));
  };
  const std::string header_line = "line " + std::to_string(s.header_index + 1);
  std::set<std::size_t> rows{data.front(), data[data.size() / 2], data.back()};
  const std::vector<std::pair<std::string, std::string>> cells{
      {"empty", ""},           {"type-string", "ten"},   {"nan", "nan"},       {"inf", "inf"},
      {"-inf", "-inf"},        {"negative", "-1"},       {"zero", "0"},        {"huge", "1e300"},
      {"tiny", "1e-300"},      {"overflow", "1e999"},    {"control-chars", "1\x01\x1b"},
      {"comma", "1,2"},        {"quote", "\"1"},         {"newline", "1\n2"},  {"quoted-newline", "\"1\n2\""},
      {"long-string", std::string(kLongString, '7')},
  };
  for (std::size_t col = 0; col < header.size(); ++col) {
    for (std::size_t row : rows) {
      for (const auto& [cls, text] : cells) {
        Edit e;
        e.op = Op::CsvCell;
        e.row = row;
        e.column = col;
        e.text = text;
        add("column " + header[col] + ", line " + std::to_string(row + 1), cls, e,
            {"line " + std::to_string(row + 1), "column " + header[col]}, false);
      }
    }
    Edit drop;
    drop.op = Op::CsvDropColumn;
    drop.column = col;
    add("column " + header[col], "absent", drop, {header_line, "column " + header[col]}, false);
  }
  for (const char* variant : {"header-only", "no-header", "empty-file", "extra-field", "missing-field",
                              "blank-line", "crlf", "bom", "many-rows", "duplicate-header", "long-line"}) {
    Edit e;
    e.op = Op::CsvRawLines;
    e.text = variant;
    add("(file)", variant, e, {}, true);
  }
}

std::vector<std::string> csv_variant(const Source& s, const Edit& e) {
  std::vector<std::string> l = s.lines;
  const std::size_t h = s.header_index;
  std::vector<std::size_t> data;
  for (std::size_t i = h + 1; i < l.size(); ++i)
    if (!l[i].empty() && l[i][0] != '#') data.push_back(i);
  const std::string& v = e.text;
  if (v == "header-only") {
    l.resize(h + 1);
  } else if (v == "no-header") {
    l.erase(l.begin() + static_cast<long>(h));
  } else if (v == "empty-file") {
    l.clear();
  } else if (v == "extra-field") {
    l[data.front()] += ",1";
  } else if (v == "missing-field") {
    l[data.front()] = l[data.front()].substr(0, l[data.front()].rfind(','));
  } else if (v == "blank-line") {
    l.insert(l.begin() + static_cast<long>(data[data.size() / 2]), "");
  } else if (v == "crlf") {
    for (std::string& x : l) x += '\r';
  } else if (v == "bom") {
    l.front() = "\xEF\xBB\xBF" + l.front();
  } else if (v == "many-rows") {
    std::vector<std::string> rows;
    for (std::size_t i : data) rows.push_back(l[i]);
    while (l.size() < kManyRows) l.push_back(rows[l.size() % rows.size()]);
  } else if (v == "duplicate-header") {
    const std::vector<std::string> f = split_fields(l[h]);
    l[h] += "," + f.front();
    for (std::size_t i : data) l[i] += "," + split_fields(l[i]).front();
  } else if (v == "long-line") {
    l[data.front()] += "," + std::string(kLongString, '9');
  }
  return l;
}

void write_csv_case(const Source& s, const Edit& e, const fs::path& file) {
  std::vector<std::string> l;
  if (e.op == Op::CsvCell) {
    l = s.lines;
    std::vector<std::string> f = split_fields(l[e.row]);
    if (e.column < f.size()) f[e.column] = e.text;
    l[e.row] = join_fields(f);
  } else if (e.op == Op::CsvDropColumn) {
    l = s.lines;
    for (std::size_t i = s.header_index; i < l.size(); ++i) {
      if (l[i].empty() || l[i][0] == '#') continue;
      std::vector<std::string> f = split_fields(l[i]);
      if (e.column < f.size()) f.erase(f.begin() + static_cast<long>(e.column));
      l[i] = join_fields(f);
    }
  } else if (e.op == Op::CsvRawLines) {
    l = csv_variant(s, e);
  }
  std::string text;
  for (const std::string& x : l) text += x + "\n";
  write_text(file, text);
}

// ------------------------------------------------------------------------------------------
// Staging: the mutated file beside copies of what it refers to
// ------------------------------------------------------------------------------------------

const Source* find_source(const std::vector<Source>& sources, const fs::path& p) {
  const fs::path want = fs::weakly_canonical(p);
  for (const Source& s : sources)
    if (fs::weakly_canonical(s.path) == want) return &s;
  return nullptr;
}

// Rewrites a relative path key to the copy's bare file name (the copies sit side by side).
// A profile file: TOML, or a measured profile (CSV).
bool is_profile_path(const std::string& s) {
  return is_toml_path(s) || (s.size() > 4 && s.compare(s.size() - 4, 4, ".csv") == 0);
}

void rebase(toml::table& root, const char* table, const char* key) {
  toml::table* t = table ? root[table].as_table() : &root;
  if (!t) return;
  if (auto v = (*t)[key].value<std::string>(); v && is_profile_path(*v))
    t->insert_or_assign(key, fs::path(*v).filename().string());
}

void rebase_paths(Kind kind, toml::table& root) {
  switch (kind) {
    case Kind::Scene: {
      rebase(root, "lifters", "profile");
      if (toml::array* a = root["lifters"]["pattern"].as_array())
        for (auto& n : *a)
          if (auto v = n.value<std::string>(); v && is_profile_path(*v)) n.as_string()->get() = fs::path(*v).filename().string();
      break;
    }
    case Kind::Profile: rebase(root, nullptr, "match_area_of"); break;
    case Kind::Screen: {
      rebase(root, "screen", "base");
      rebase(root, "screen", "equal_area");
      if (toml::array* a = root["family"]["profiles"].as_array())
        for (auto& n : *a)
          if (auto v = n.value<std::string>(); v && is_toml_path(*v)) n.as_string()->get() = fs::path(*v).filename().string();
      break;
    }
    case Kind::Comparison: {
      if (toml::array* a = root["comparison"]["designs"].as_array())
        for (auto& n : *a)
          if (auto v = n.value<std::string>(); v && is_toml_path(*v)) n.as_string()->get() = fs::path(*v).filename().string();
      break;
    }
    default: break;
  }
}

// Copies a shipped TOML file into dir with its path keys rebased (profiles: all of them).
void copy_rebased(const Source& s, const fs::path& dir) {
  toml::table root = *s.doc;
  rebase_paths(s.kind, root);
  write_toml(dir / s.path.filename(), root, 0);
}

std::string profile_of(const Source& scene) {
  if (auto v = (*scene.doc)["lifters"]["profile"].value<std::string>()) return *v;
  return "";
}

// The files a TOML source refers to (scenes of a comparison or screen), resolved.
std::vector<fs::path> referenced_scenes(const Source& s) {
  std::vector<fs::path> out;
  const fs::path dir = s.path.parent_path();
  if (s.kind == Kind::Comparison) {
    if (const toml::array* a = (*s.doc)["comparison"]["designs"].as_array())
      for (const auto& n : *a)
        if (auto v = n.value<std::string>()) out.push_back((dir / *v).lexically_normal());
  } else if (s.kind == Kind::Screen) {
    if (auto v = (*s.doc)["screen"]["base"].value<std::string>()) out.push_back((dir / *v).lexically_normal());
  }
  return out;
}

}  // namespace

const char* kind_name(Kind k) {
  switch (k) {
    case Kind::Scene: return "scene";
    case Kind::Profile: return "profile";
    case Kind::Comparison: return "comparison";
    case Kind::Screen: return "screen";
    case Kind::Survey: return "survey";
    case Kind::Hardness: return "hardness";
  }
  return "?";
}

std::string path_text(const Path& p) {
  std::string s;
  for (const PathStep& st : p) {
    if (st.index >= 0) {
      s += "[" + std::to_string(st.index) + "]";
    } else {
      if (!s.empty()) s += ".";
      s += st.key;
    }
  }
  return s;
}

std::vector<Source> discover_sources(const fs::path& root) {
  std::vector<Source> out;
  auto files = [&](const char* dir, const char* ext) {
    std::vector<fs::path> v;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(root / dir, ec))
      if (e.is_regular_file() && e.path().extension() == ext) v.push_back(e.path());
    std::sort(v.begin(), v.end());
    return v;
  };
  for (const char* dir : {"scenarios", "tests/data", "validation", "profiles"}) {
    for (const fs::path& p : files(dir, ".toml")) {
      Source s;
      s.path = p;
      s.rel = fs::relative(p, root).string();
      s.doc = toml::parse_file(p.string());
      if (std::string(dir) == "profiles") s.kind = Kind::Profile;
      else if (s.doc->contains("comparison")) s.kind = Kind::Comparison;
      else if (s.doc->contains("screen")) s.kind = Kind::Screen;
      else s.kind = Kind::Scene;
      out.push_back(std::move(s));
    }
  }
  for (const char* dir : {"validation", "tests/data"}) {
    for (const fs::path& p : files(dir, ".csv")) {
      Source s;
      s.path = p;
      s.rel = fs::relative(p, root).string();
      s.lines = split_lines(read_text(p));
      std::size_t h = 0;
      while (h < s.lines.size() && (s.lines[h].empty() || s.lines[h][0] == '#')) ++h;
      if (h == s.lines.size()) continue;
      s.header_index = h;
      const std::vector<std::string> cols = split_fields(s.lines[h]);
      auto has = [&](const char* c) { return std::find(cols.begin(), cols.end(), c) != cols.end(); };
      if (has("hardness")) s.kind = Kind::Hardness;
      else if (has("hours")) s.kind = Kind::Survey;
      else continue;
      out.push_back(std::move(s));
    }
  }
  return out;
}

std::vector<Case> build_cases(const std::vector<Source>& sources) {
  std::vector<Case> out;
  for (const Source& s : sources) {
    Case base;
    base.source = &s;
    base.key = "(none)";
    base.value_class = "original";
    base.baseline = true;
    base.edit.op = s.doc ? Op::SetEmptyArray : Op::CsvRawLines;  // unused for a baseline
    out.push_back(base);
    if (s.doc) {
      Builder b{s, out};
      Path root;
      b.add(root, "unknown-key", Builder::op(Op::AddUnknownKey), {kUnknownKey});
      b.walk(*s.doc, root);
    } else {
      csv_cases(s, out);
    }
  }
  for (std::size_t i = 0; i < out.size(); ++i) out[i].id = i;
  return out;
}

Staged stage_case(const Case& c, const std::vector<Source>& sources, const fs::path& dir) {
  const Source& s = *c.source;
  fs::create_directories(dir);
  // Every shipped profile beside the case: they refer to each other by bare file names.
  for (const Source& p : sources)
    if (p.kind == Kind::Profile) copy_rebased(p, dir);
  // The shipped measured profiles (CSV) too, as they are.
  {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(fs::path(MILLWEAR_SOURCE_DIR) / "profiles", ec))
      if (e.is_regular_file() && e.path().extension() == ".csv")
        fs::copy_file(e.path(), dir / e.path().filename(), fs::copy_options::overwrite_existing, ec);
  }
  Staged st;
  st.primary = dir / s.path.filename();
  if (s.doc) {
    for (const fs::path& ref : referenced_scenes(s))
      if (const Source* r = find_source(sources, ref)) copy_rebased(*r, dir);
    toml::table root = *s.doc;
    rebase_paths(s.kind, root);
    std::size_t long_len = 0;
    if (!c.baseline) {
      apply_toml_edit(root, c.edit);
      if (c.edit.op == Op::LongString) long_len = c.edit.count;
    }
    write_toml(st.primary, root, long_len);
    if (s.kind == Kind::Profile) {
      // A shipped scene using this profile, else the first SAG-size scene with it swapped in.
      const Source* host = nullptr;
      for (const Source& sc : sources)
        if (sc.kind == Kind::Scene && fs::path(profile_of(sc)).filename() == s.path.filename()) { host = &sc; break; }
      if (!host)
        for (const Source& sc : sources)
          if (sc.kind == Kind::Scene && sc.rel == "scenarios/sag-2x30.toml") { host = &sc; break; }
      if (!host)
        for (const Source& sc : sources)
          if (sc.kind == Kind::Scene) { host = &sc; break; }
      toml::table h = *host->doc;
      h["lifters"].as_table()->insert_or_assign("profile", s.path.filename().string());
      st.host_scene = dir / ("host-" + host->path.filename().string());
      write_toml(st.host_scene, h, 0);
    }
  } else {
    if (c.baseline) {
      Edit keep;
      keep.op = Op::CsvCell;
      keep.row = s.header_index;
      keep.column = std::numeric_limits<std::size_t>::max();
      write_csv_case(s, keep, st.primary);
    } else {
      write_csv_case(s, c.edit, st.primary);
    }
    if (s.kind == Kind::Survey) st.host_scene = stage_survey_scene(sources, dir);
  }
  return st;
}

fs::path stage_survey_scene(const std::vector<Source>& sources, const fs::path& dir) {
  fs::create_directories(dir);
  for (const Source& p : sources)
    if (p.kind == Kind::Profile) copy_rebased(p, dir);
  for (const Source& s : sources)
    if (s.kind == Kind::Scene && s.rel == "scenarios/lab-mill.toml") {
      copy_rebased(s, dir);
      return dir / s.path.filename();
    }
  throw std::runtime_error("scenarios/lab-mill.toml (the scene of the survey examples) not found");
}

}  // namespace mutation
