#pragma once
// The shipped input files and the hostile edits tried on them: every key of every TOML
// input (scenes, profiles, comparison and screen files) and every column and row kind of
// the CSV inputs (surveys, hardness periods), each given a set of hostile values.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <toml++/toml.h>

namespace mutation {

namespace fs = std::filesystem;

enum class Kind { Scene, Profile, Comparison, Screen, Survey, Hardness };
const char* kind_name(Kind k);

// One shipped input file, read once.
struct Source {
  Kind kind = Kind::Scene;
  fs::path path;                    // absolute
  std::string rel;                  // relative to the source tree, for reports
  std::optional<toml::table> doc;   // TOML files
  std::vector<std::string> lines;   // CSV files, without their newlines
  std::size_t header_index = 0;     // CSV: index in `lines` of the header row
};

// A step from a TOML root to a node: a key of a table, or an element of an array.
struct PathStep {
  std::string key;
  long index = -1;  // >= 0: array element
};
using Path = std::vector<PathStep>;
std::string path_text(const Path& p);

enum class Op {
  Remove,        // the key (or array element) is removed
  SetString, SetInteger, SetFloat, SetBool,
  SetEmptyTable, SetEmptyArray,
  WrapInArray,   // [original]
  LongArray,     // the array's elements repeated to `count` elements
  AddUnknownKey, // a key the table does not know
  LongString,    // a string of `count` characters
  ManySizes,     // `count` sizes, each with mass fraction 1/count
  EmptyTable,    // every key of the table removed
  // CSV edits
  CsvCell,       // row `row`, column `column` becomes `text` (raw, may break the row)
  CsvDropColumn, // column `column` removed from the header and every row
  CsvRawLines,   // the file's lines replaced by a variant (see csv_variant)
};

struct Edit {
  Op op = Op::Remove;
  Path path;             // TOML
  std::string text;      // string value, CSV cell text, or CSV variant name
  std::int64_t integer = 0;
  double number = 0.0;
  bool boolean = false;
  std::size_t count = 0;
  std::size_t row = 0;   // CSV: index in Source::lines
  std::size_t column = 0;
};

struct Case {
  std::size_t id = 0;
  const Source* source = nullptr;
  std::string key;          // dotted key as the program names it; CSV: "column NAME" / "line N" / "(file)"
  std::string value_class;  // "nan", "absent", "long-string", ...
  Edit edit;
  // What a refusal should name: exact locations ("mill.speed", "line 12"), or with a
  // trailing '*' any location starting with the rest ("lifters.*"); any_line: any "line N".
  std::vector<std::string> locations;
  bool any_line = false;
  bool baseline = false;    // the unmutated file (expected to pass)
};

std::vector<Source> discover_sources(const fs::path& source_dir);
std::vector<Case> build_cases(const std::vector<Source>& sources);

// The inputs of one case written into `dir`: the mutated file, and copies of every file it
// refers to (path keys rewritten to the copies' names unless the case mutates that key).
struct Staged {
  fs::path primary;        // the mutated file
  fs::path host_scene;     // profiles: a scene that uses the mutated profile; surveys: the scene
};
Staged stage_case(const Case& c, const std::vector<Source>& sources, const fs::path& dir);

// The scene the survey files belong to (their README: made from a run of it), staged into dir.
fs::path stage_survey_scene(const std::vector<Source>& sources, const fs::path& dir);

}  // namespace mutation
