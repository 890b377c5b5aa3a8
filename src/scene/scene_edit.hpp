#pragma once
// Editing a scene file's text, keeping everything the user wrote: the calibrated copy of a
// scene that `millwear calibrate` writes is the scene's own text with one wear-rate line
// replaced (and the lifter profile path re-pointed, since the copy may live in another
// folder), so its comments, layout and every other key survive.
#include <string>

namespace millwear {

struct WearRateEdit {
  double wear_rate_m3_per_J = 0.0;  // written with 6 significant digits
  std::string note;                 // why: goes after the value and into the header line
  std::string out_dir;              // folder the copy goes to: the profile path is made to
                                    // resolve from there
};

// The text of a scene file with its wear-rate key (wear.wear_rate, wear.area_loss_rate or
// wear.height_loss_rate, whichever it has) replaced by `wear_rate = C   # m^3/J, NOTE`, the
// key's line from the key to the line end (its old comment too); lifters.profile, when
// the copy goes to another folder than the scene, rewritten relative to out_dir (absolute
// when that climbs out more than one folder); and a first comment line naming the source
// and the note. `scene_path` names the file in errors and resolves the profile path.
// Throws InputError: the text is not TOML, or it has no [wear] table or no wear-rate key in
// it. Throws RunError when a key sits where a one-line edit cannot reach it.
std::string calibrated_scene_text(const std::string& text, const std::string& scene_path,
                                  const WearRateEdit& edit);

}  // namespace millwear
