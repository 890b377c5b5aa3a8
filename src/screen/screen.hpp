#pragma once
// Screening lifter designs: a family of candidate lifters on one base scene, sampled as a
// full grid or a Latin hypercube, each candidate written as a profile and a scene file and
// validated the way `millwear run` would read it (rejected ones are listed with the reason,
// never a crash). The ranking of finished designs lives in screen/ranking.hpp, the job
// lists for GNU parallel and Slurm arrays in screen/jobs.hpp.
//
// Screen file (TOML), every key checked like a scene file's (file, dotted key, expectation,
// line; InputError -> exit 2):
//
//   [screen]
//   name = "sag-face-angle"          # optional (default: the file's stem)
//   base = "sag-2x30.toml"           # base scene: mill, charge, solver, wear (relative path)
//   fidelity = "draft"               # optional override of the base scene's fidelity
//   stages = 4                       # optional override of wear.stages
//   stage_hours = 750.0              # optional override of wear.stage_hours
//   sampling = "grid"                # "grid" (every combination) or "latin_hypercube"
//   samples = 20                     # latin_hypercube: number of candidates
//   seed = 1                         # latin_hypercube: random seed
//   equal_area = "base"              # optional: "base" (the base scene's lifter) or a profile
//                                    # file; each candidate's top width is chosen so its metal
//                                    # area equals the reference's. With a base scene of a
//                                    # pattern of kinds (hi-lo): "base" matches each kind to its
//                                    # own kind's area, or a list of files, one per kind
//   power = "min"                    # Pareto sense of power draw: "min" (a cost) or "max"
//
//   [family]                         # each: a number, a list, or {min, max, steps}
//   height = 200.0                   # mm
//   top_width = 100.0                # mm (not with equal_area)
//   leading_face_angle = {min = 10.0, max = 40.0, steps = 7}   # deg from radial
//   trailing_face_angle = 5.0        # deg
//   symmetric = false                # true: trailing face angle = leading face angle
//   rows = [36, 48]                  # lifter rows (integers)
//   direction = ["uni", "bi"]        # uni = forward, bi = bidirectional
//   profiles = ["a.toml", "b.toml"]  # instead of the trapezoid keys: profile files
//
// A key not given takes the base scene's value (its lifter must be a trapezoid for the
// trapezoid keys). In a grid, a {min, max, steps} range is `steps` evenly spaced values;
// in a Latin hypercube a range without steps is sampled continuously, one value per
// stratum, and a list one level per stratum.
//
// A base scene with a [lifters] pattern (kinds of lifter repeating over the rows, e.g. hi-lo)
// gives candidates of the same pattern: each kind a trapezoid whose parameters the family
// gives where it has them (the same value for every kind) and the base kind's own where it
// does not (so a face-angle family keeps the high and the low lifters' heights). Not with
// family.profiles.
//
// `--set KEY=VALUE` overrides (ScreenDef::overrides) go over the base scene before anything
// is read from it, as in every command that reads a scene, and are written into every
// candidate's scene file: the local pool, GNU parallel and Slurm tasks read them there. A key
// the screen sets for every candidate itself (name, the lifters, and rows, direction,
// fidelity, stages or stage hours when the screen file gives them) is refused.
#include <cstdint>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace millwear::screen {

enum class Sampling { Grid, LatinHypercube };

// One parameter of the family: fixed (one value), a list of values, or a range.
struct Axis {
  std::vector<double> values;  // fixed or listed values (or grid points of a range)
  bool is_range = false;       // {min, max} without steps: continuous (Latin hypercube only)
  double min = 0.0, max = 0.0;
  bool given = false;          // the screen file set it
  bool varies() const { return is_range || values.size() > 1; }
};

struct ScreenDef {
  std::string name;
  std::string base_scene;        // resolved path
  std::string fidelity;          // "" = the base scene's
  int stages = 0;                // 0 = the base scene's
  double stage_hours = 0.0;      // 0 = the base scene's
  Sampling sampling = Sampling::Grid;
  int samples = 0;
  std::uint64_t seed = 1;
  std::string equal_area;        // "" none, "base", or a resolved profile file
  std::vector<std::string> equal_area_kinds;  // equal_area as a list: one resolved file per kind
  std::vector<std::string> overrides;         // --set KEY=VALUE over the base scene, in order
  int kinds = 1;                 // kinds of lifter of the base scene (its pattern's; 1 without)
  bool power_higher_is_better = false;
  // Family, file units (mm, deg).
  Axis height_mm, top_width_mm, leading_deg, trailing_deg, rows;
  bool symmetric = false;
  std::vector<std::string> directions;  // "uni" / "bi"; empty = the base scene's
  std::vector<std::string> profiles;    // resolved profile files; empty = trapezoid family
};

// Read and validate a screen file and its base scene (with the --set overrides on it).
// Throws InputError.
ScreenDef load_screen(const std::string& path, const std::vector<std::string>& overrides = {});

// One kind of lifter of a candidate whose base scene has a pattern. Numbers in file units.
struct KindShape {
  double height_mm = 0.0, top_width_mm = 0.0, leading_deg = 0.0, trailing_deg = 0.0;
  double area_mm2 = 0.0;
  std::string profile_file;       // written profile (relative to OUT)
};

// One candidate lifter design. Numbers in file units (mm, deg).
struct Candidate {
  int sample = 0;                 // index in the sampled family (names it: d007)
  std::string name;
  std::string profile_source;     // profiles mode: the file; else empty (a trapezoid)
  double height_mm = 0.0, top_width_mm = 0.0, leading_deg = 0.0, trailing_deg = 0.0;
  int rows = 0;
  std::string direction;          // "uni" / "bi"
  double area_mm2 = 0.0;
  std::string reason;             // non-empty: rejected, and why
  std::string scene_file, profile_file;  // written candidate files (relative to OUT)
  // A base scene with a pattern: every kind's lifter, kind 0's also in the fields above.
  // Empty for a plain liner.
  std::vector<KindShape> kinds;
};

// The candidates of the family in a fixed order (grid: the last parameter varies fastest;
// Latin hypercube: sample order). Pure: same definition and base -> same candidates.
// Candidates whose shape cannot be made (no top width gives the reference area) come back
// with a reason.
std::vector<Candidate> sample_family(const ScreenDef& def, const Scene& base);
// InputError (naming the screen file's screen.samples) if two candidates are one design: a
// Latin hypercube over listed values draws a value for every sample, and two samples can
// draw the same values of every parameter.
void check_distinct_candidates(const std::vector<Candidate>& candidates, const std::string& screen_file);

// The parameters that vary in the family, by column name (height_mm, leading_face_angle_deg, ...).
std::vector<std::string> varying_parameters(const ScreenDef& def);

// Writes OUT/candidates/NAME.toml (the base scene, with the --set overrides, and the
// candidate's name, lifter, rows, direction and the screen's overrides) and NAME-profile.toml
// (a pattern: NAME-kK-profile.toml per kind K) for every candidate without
// a reason, then reads each back with load_scene and builds its mill: a candidate that
// fails (self-intersecting or zero-area profile, lifters touching their neighbours, too
// tall, below the replacement height) gets the reason and its files are removed.
void write_candidates(const ScreenDef& def, std::vector<Candidate>& candidates, const std::string& out);

// OUT/designs.csv (valid candidates, in task order: row I is `screen-task OUT I`) and
// OUT/rejected.csv (the others, with the reason). Candidates of a pattern add the columns
// kindK_height_mm, kindK_top_width_mm, kindK_leading_face_angle_deg,
// kindK_trailing_face_angle_deg, kindK_area_mm2, kindK_profile_file for every kind K.
void write_design_tables(const std::string& out, const std::vector<Candidate>& candidates);
// Reads OUT/designs.csv back (what every task and --collect use). Throws InputError.
std::vector<Candidate> read_designs(const std::string& out);

// Paths in OUT.
std::string designs_csv(const std::string& out);      // OUT/designs.csv
std::string rejected_csv(const std::string& out);     // OUT/rejected.csv
std::string ranking_csv(const std::string& out);      // OUT/ranking.csv
std::string design_dir(const std::string& out, const std::string& name);  // OUT/designs/NAME
std::string task_status_path(const std::string& out, const std::string& name);  // OUT/designs/NAME/task.status

}  // namespace millwear::screen
