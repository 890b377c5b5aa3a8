#pragma once
// Layout of a run output folder, stage-done markers for --resume, the manifest's file list,
// and the mark that says which command's results a folder holds.
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
//   OUT/inputs/                          copies of the scene, profile and comparison files
//   OUT/stages/run.key                   the designs and their input fingerprints
//   OUT/.millwear.lock                   while a run writes (io/folder_lock.hpp)
// manifest.json lists every file the run wrote ("files"); `run --force` deletes exactly
// those when the folder is taken over by a run of other inputs.
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
std::string run_key_path(const std::string& out);                    // OUT/stages/run.key
std::string stage_done_marker(const std::string& out, const std::string& design, int stage);
std::string plots_out_dir(const std::string& out);                   // OUT/plots
std::string plots_data_dir(const std::string& out);                  // OUT/plots/data

// Design names become parts of file names: common/names.hpp's is_safe_name.
bool is_valid_design_name(const std::string& design);

// Creates OUT, OUT/profiles, OUT/stages, OUT/plots, OUT/plots/data. Throws RunError.
void create_run_folder(const std::string& out);

// `path` relative to `out` if it lies under it ("profiles/x.csv"), else "" (both taken as
// normal paths: "out/" and "out//x.csv" give "x.csv").
std::string relative_to(const std::string& out, const std::string& path);

// `path` is the same file as one of `files` (fs::equivalent: links and spellings resolved).
bool is_one_of(const std::string& path, const std::vector<std::string>& files);

// Deletes the files of an earlier run in OUT: each entry of `files` (relative to OUT, as a
// manifest lists them) that is a regular file, then millwear's temporaries in the folders of
// a run folder, then those folders (profiles, stages, plots/data, plots, inputs) if they
// are left empty, and the folders the listed files leave empty. An entry that is absolute, has
// a ".." part or lies in a linked folder is skipped: nothing outside OUT is touched, and no
// file that is not listed. Nor is a file of `keep`, the command's own inputs (a run started
// from the copies in OUT/inputs/). Returns how many files were removed.
int remove_run_files(const std::string& out, const std::vector<std::string>& files,
                     const std::vector<std::string>& keep = {});

// Before a command that does not resume writes OUT again (io/staging.hpp): the first of
// `names` (paths relative to OUT) that is there though its earlier run's manifest does not
// list it, as OUT/NAME; "" if none, or if OUT has no manifest. That file is a user's, which the
// command would overwrite under its own output's name.
std::string unlisted_output(const std::string& out, const std::vector<std::string>& names);

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
// K of a file named DESIGN_stageK + suffix (K digits only, at most nine); -1 for any other name.
int stage_in_file_name(const std::string& name, const std::string& design, const std::string& suffix);
// Highest K such that stages 0..K are all finished; -1 if stage 0 is not.
// A resumed run continues from K + 1.
int last_finished_stage(const std::string& out, const std::string& design);

// The `files` list of OUT/manifest.json (paths relative to OUT): what a run wrote. Empty if
// there is no manifest, it does not parse or it has no list (an older millwear's).
std::vector<std::string> manifest_files(const std::string& out);

// OUT/.millwear-results: which command writes its results into OUT ("command = NAME"). Every
// command that writes a folder marks it when it takes the folder (FolderLock, run), so that
// no other command writes into it.
std::string folder_mark_path(const std::string& out);
// Writes the mark (atomically) unless OUT already holds this command's mark.
void mark_folder(const std::string& out, const std::string& command);

// The names of a folder's entries that are not hidden (hidden: a leading '.', as the lock,
// the mark, temporaries and a file manager's files are), sorted; none if it cannot be read.
std::vector<std::string> visible_entries(const std::string& folder);

// Which command's results OUT holds: the command its mark names; else, for a folder written
// before the mark existed, "run" (OUT/stages/run.key, or a manifest.json without a
// "command"), the "command" of its manifest.json ("sweep"), "charge" (its
// charge_summary.csv); or "" (none of these).
std::string folder_results_command(const std::string& out);
// For a command other than `run` that writes into OUT, before any work: throws
// InputError(OUT, "-o", ...) if OUT holds another command's results, which this one would
// overwrite in part (a run's liner, snapshot and spectrum files, its manifest), or if it
// holds files no command recorded (the user's own, which a file of the same name would
// replace; `run`, which tells its own files apart, keeps them beside its results).
void check_folder_not_taken(const std::string& out, const std::string& command);

// Before a command writes its files into OUT, ahead of any work: throws InputError(PATH, "-o",
// ...) for the first of `files` (paths relative to OUT, "plots/x.png") that is a folder, since
// a file is written by renaming a temporary over its name and no rename replaces a folder, or
// whose folder on the way (OUT/plots) is a file (a link to a folder is one). `command` names
// the writer in the message. Nothing is made or removed.
void check_output_names(const std::string& out, const std::vector<std::string>& files, const std::string& command);

// An input of the command that is one of `files` in OUT (paths relative to OUT; the same file
// by any path or link) would be overwritten or deleted by the command that reads it: throws
// InputError(INPUT, "-o", ...) naming both, before any work.
void check_inputs_not_among(const std::string& out, const std::vector<std::string>& files,
                            const std::vector<std::string>& inputs, const std::string& command);

}  // namespace millwear::io
