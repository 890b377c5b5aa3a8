#pragma once
// A script of timed control changes for `millwear view --script FILE`: the same controls the
// panel has, at given times, so a demonstration (or a test) runs without a person.
//
// One command a line, `TIME COMMAND ARGS...`, TIME in seconds of frames since the view
// started (each frame 1/60 s; at time scale 1 that is the simulated time unless the mill was
// paused or wearing); `#` starts a comment. Commands (units as in the panel):
//   speed F                  fraction of critical speed
//   filling F [BALL]         mill filling and ball filling (fractions; BALL keeps the scene's)
//   direction forward|reverse
//   profile FILE             a lifter profile file (relative to the script)
//   lifter H LEAD TRAIL      parametric lifter: height mm, face angles deg
//   pause | resume | reset
//   time_scale S
//   colour species|speed
//   trails N
//   wear HOURS               start the wear mode for HOURS of operation
//   wait_wear                hold the frames until the wear history ends
//   save_scene FILE          the scene as edited (relative to the working folder)
//   save_profiles DIR        the wear history's profiles as `millwear run` writes them
//   screenshot FILE          the window as a PNG
//   record DIR | stop_record frames as DIR/frame_NNNNN.png
//   report                   one line of readouts (time, disks, power, toe, shoulder...)
//   quit
#include <string>
#include <vector>

namespace millwear::view {

struct ScriptCommand {
  double time_s = 0.0;
  std::string name;
  std::vector<std::string> args;
  int line = 0;
};

// Reads and checks the whole script before anything runs: InputError(file, "line N", ...)
// for an unknown command, a wrong argument count or a value that is not a number. Commands
// come back in time order (stable: same time, file order).
std::vector<ScriptCommand> read_script(const std::string& file);

}  // namespace millwear::view
