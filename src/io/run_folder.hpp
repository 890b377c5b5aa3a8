#pragma once
// Layout of a run output folder, stage-done markers for --resume, and a minimal JSON
// writer for the manifest.
//
//   OUT/manifest.json                    program version, seed, fidelity, settings, wall times
//   OUT/summary.csv                      one row per design and stage
//   OUT/spectrum.csv                     collision-energy spectrum per design
//   OUT/profiles/DESIGN_stageK.csv       lifter profile after stage K (mm, lifter-local)
//   OUT/snapshot_DESIGN.csv              charge snapshot (disks)
//   OUT/liner_DESIGN.csv                 liner segments with wear rate
//   OUT/stages/DESIGN_stageK.done        marker: stage K of DESIGN is complete on disk
//   OUT/plots/                           figures (PNG + SVG), gnuplot.log
//   OUT/plots/data/                      per-design files split out for gnuplot
//
// Stage-done marker format (key=value text, one pair a line, '#' starts a comment line,
// blank lines ignored; the key is trimmed, the value is everything after the first '='
// with surrounding spaces trimmed):
//   # millwear stage marker
//   design=2x30
//   stage=2
//   ...any further keys the writer adds (hours, wall_s, state file names)
// A marker is written atomically, after every file of its stage, so its existence alone
// means the stage is complete.
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace millwear::io {

// ---- path conventions ----
std::string join_path(const std::string& a, const std::string& b);
std::string manifest_path(const std::string& out);                   // OUT/manifest.json
std::string summary_path(const std::string& out);                    // OUT/summary.csv
std::string spectrum_path(const std::string& out);                   // OUT/spectrum.csv
std::string profiles_dir(const std::string& out);                    // OUT/profiles
std::string profile_path(const std::string& out, const std::string& design, int stage);
std::string snapshot_path(const std::string& out, const std::string& design);
std::string liner_path(const std::string& out, const std::string& design);
std::string stages_dir(const std::string& out);                      // OUT/stages
std::string stage_done_marker(const std::string& out, const std::string& design, int stage);
std::string plots_out_dir(const std::string& out);                   // OUT/plots
std::string plots_data_dir(const std::string& out);                  // OUT/plots/data

// Design names become parts of file names: letters, digits, '.', '-', '_' and not
// starting with '.'; at most 64 characters.
bool is_valid_design_name(const std::string& design);

// Creates OUT, OUT/profiles, OUT/stages, OUT/plots, OUT/plots/data. Throws RunError.
void create_run_folder(const std::string& out);

// ---- key=value files ----
using KeyValues = std::vector<std::pair<std::string, std::string>>;  // in file order

// Text of a key=value file with a leading comment line. Throws std::invalid_argument if a
// key is empty or contains '=' or a line end, or a value contains a line end.
std::string format_key_values(const KeyValues& kv, const std::string& comment = "");
// Parses key=value text; `name` is used in errors: InputError(name, "line N", "key=value").
KeyValues parse_key_values(const std::string& text, const std::string& name);
KeyValues read_key_values(const std::string& path);
// The value of a key, or `fallback` if absent.
std::string find_value(const KeyValues& kv, const std::string& key,
                       const std::string& fallback = "");

// ---- stage markers ----
// Writes OUT/stages/DESIGN_stageK.done atomically with design=, stage= then `extra`.
// Creates OUT/stages if needed. Call it after every other file of the stage is written.
void write_stage_done(const std::string& out, const std::string& design, int stage,
                      const KeyValues& extra = {});
// Stage numbers K with a marker OUT/stages/DESIGN_stageK.done, ascending. A marker that
// does not parse, or whose design=/stage= disagree with its name, is not counted.
std::vector<int> list_finished_stages(const std::string& out, const std::string& design);
// Highest K such that stages 0..K are all finished; -1 if stage 0 is not.
// A resumed run continues from K + 1.
int last_finished_stage(const std::string& out, const std::string& design);

// ---- minimal JSON writer (manifest) ----
// One recursive value type: null, bool, number, string, array or object. A default-made
// value is an empty object, so `JsonObject m; m.set("seed", 42).object("settings")...`
// reads naturally. Object keys print in insertion order; set() on an existing key
// replaces its value in place. Doubles print in the shortest form that reads back exactly
// (up to 17 digits); NaN and infinities print as null (JSON has neither).
class JsonValue {
 public:
  enum class Kind { Null, Bool, Number, Integer, String, Array, Object };
  JsonValue() : kind_(Kind::Object) {}
  JsonValue(std::nullptr_t) : kind_(Kind::Null) {}
  JsonValue(bool b) : kind_(Kind::Bool), b_(b) {}
  JsonValue(double d) : kind_(Kind::Number), d_(d) {}
  JsonValue(float d) : kind_(Kind::Number), d_(d) {}
  JsonValue(int i) : kind_(Kind::Integer), i_(i) {}
  JsonValue(long i) : kind_(Kind::Integer), i_(i) {}
  JsonValue(long long i) : kind_(Kind::Integer), i_(i) {}
  JsonValue(unsigned i) : kind_(Kind::Integer), i_(static_cast<long long>(i)) {}
  JsonValue(unsigned long i) : kind_(Kind::Integer), i_(static_cast<long long>(i)) {}
  JsonValue(unsigned long long i) : kind_(Kind::Integer), i_(static_cast<long long>(i)) {}
  JsonValue(const char* s) : kind_(Kind::String), s_(s) {}
  JsonValue(std::string s) : kind_(Kind::String), s_(std::move(s)) {}

  static JsonValue array() { JsonValue v; v.kind_ = Kind::Array; return v; }
  static JsonValue object() { return JsonValue(); }

  Kind kind() const { return kind_; }

  // Object: sets key to v (turns a null value into an object). Returns *this for chaining.
  // Throws std::logic_error on a value that is neither null nor an object.
  JsonValue& set(const std::string& key, JsonValue v);
  // Object: the value under key, created as an empty object if absent; returns it so
  // nested objects can be filled in place.
  JsonValue& object(const std::string& key);
  bool has(const std::string& key) const;
  // Array: appends v (turns a null or empty object into an array). Returns *this.
  JsonValue& push(JsonValue v);
  std::size_t size() const;  // members or items; 0 for scalars

  // Pretty-printed with `indent` spaces per level (0: one line), without final newline.
  std::string dump(int indent = 2) const;

 private:
  void dump_to(std::string& out, int indent, int depth) const;
  Kind kind_;
  bool b_ = false;
  double d_ = 0.0;
  long long i_ = 0;
  std::string s_;
  std::vector<JsonValue> items_;                            // Array
  std::vector<std::pair<std::string, JsonValue>> members_;  // Object, insertion order
};
using JsonObject = JsonValue;

// JSON string escaping (quotes included).
std::string json_quote(const std::string& s);

}  // namespace millwear::io
