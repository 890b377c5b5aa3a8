#pragma once
// Editing a scene file's text, keeping everything the user wrote: the calibrated copy of a
// scene that `millwear calibrate` writes is the scene's own text with one wear-rate line
// replaced (and the lifter profile path re-pointed, since the copy may live in another
// folder), so its comments, layout and every other key survive.
#include <string>
#include <vector>

namespace millwear {

struct WearRateEdit {
  double wear_rate_m3_per_J = 0.0;  // written with 6 significant digits
  std::string note;                 // why: goes after the value and into the header line
  std::string out_dir;              // folder the copy goes to: the profile path is made to
                                    // resolve from there
};

// How a calibrated copy's first line begins: calibrate replaces only a file that begins so.
constexpr const char* kCalibratedCopyHeader = "# Calibrated copy of";

// The text of a scene file with its wear-rate key (wear.wear_rate, wear.area_loss_rate or
// wear.height_loss_rate, whichever it has) replaced by `wear_rate = C   # m^3/J, NOTE`, the
// key's line from the key to the line end (its old comment too); lifters.profile (or each
// profile of lifters.pattern), when the copy goes to another folder than the scene, rewritten
// relative to out_dir (absolute when that climbs out more than one folder); and a first
// comment line naming the source
// and the note. `scene_path` names the file in errors and resolves the profile path.
// Throws InputError: the text is not TOML, or it has no [wear] table or no wear-rate key in
// it. Throws RunError when a key sits where a one-line edit cannot reach it.
std::string calibrated_scene_text(const std::string& text, const std::string& scene_path,
                                  const WearRateEdit& edit);

// One key of a scene set to a value: `table.key = value`, value as TOML text (a number, a
// quoted string). A key named in `replaces` (speed_rpm for speed) goes in its place.
struct KeyEdit {
  std::string table;
  std::string key;
  std::string value;
  std::vector<std::string> replaces;
};

// The text of a scene file with each edit applied: the key's line (or the line of a key it
// replaces) from the key to the end of its value rewritten, or `key = value` added at the
// end of its table (a new table at the end of the file when there is none). Comments and
// every other key stay, but for the comment of an edited line whose old value was not a
// number (it named the old choice) or whose key was removed or replaced. lifters.profile or lifters.pattern, unless the profile is edited, is
// re-pointed to resolve from out_dir as in calibrated_scene_text. A non-empty header goes first as a comment line.
// Throws InputError: the text is not TOML; RunError: a key sits where a one-line edit
// cannot reach it (value over several lines, an inline table).
std::string edited_scene_text(const std::string& text, const std::string& scene_path,
                              const std::vector<KeyEdit>& edits, const std::string& out_dir,
                              const std::string& header);

// A string as a TOML value (literal quotes unless it holds one).
std::string toml_string_value(const std::string& s);

}  // namespace millwear
