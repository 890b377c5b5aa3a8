// Reading a view script (see script.hpp).
#include "view/script.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "common/errors.hpp"
#include "scene/limits.hpp"

namespace millwear::view {

namespace {

struct Shape {
  int min_args, max_args;
  int numbers;  // leading arguments that must be numbers
};

const std::map<std::string, Shape>& commands() {
  static const std::map<std::string, Shape> c{
      {"speed", {1, 1, 1}},      {"filling", {1, 2, 2}},    {"direction", {1, 1, 0}},
      {"profile", {1, 1, 0}},    {"lifter", {3, 3, 3}},     {"pause", {0, 0, 0}},
      {"resume", {0, 0, 0}},     {"reset", {0, 0, 0}},      {"time_scale", {1, 1, 1}},
      {"colour", {1, 1, 0}},     {"trails", {1, 1, 1}},     {"wear", {1, 1, 1}},
      {"wait_wear", {0, 0, 0}},  {"save_scene", {1, 1, 0}}, {"save_profiles", {1, 1, 0}},
      {"screenshot", {1, 1, 0}}, {"record", {1, 1, 0}},     {"stop_record", {0, 0, 0}},
      {"report", {0, 0, 0}},     {"quit", {0, 0, 0}}};
  return c;
}

// The ranges of the numbers the panel's controls also bound: the speed slider (the scene
// checker's mill.speed), the time-scale slider, the trail count, the wear mode's hours (the
// scene's operating-hours bound).
struct Range {
  double lo, hi;
  bool integer;
};
const std::map<std::string, Range>& ranges() {
  static const std::map<std::string, Range> r{{"speed", {kMinSpeedFraction, kMaxSpeedFraction, false}},
                                              {"time_scale", {0.05, 4.0, false}},
                                              {"trails", {0.0, 16.0, true}},
                                              {"wear", {1e-6, 1e6, false}}};
  return r;
}

bool is_number(const std::string& s, double& v) {
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end && *end == '\0' && !s.empty() && std::isfinite(v);
}

}  // namespace

std::vector<ScriptCommand> read_script(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file, "", "a readable script file");
  const std::filesystem::path dir = std::filesystem::path(file).parent_path();
  std::vector<ScriptCommand> out;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    if (n == 1 && line.compare(0, 3, "\xEF\xBB\xBF") == 0) line.erase(0, 3);  // a UTF-8 byte-order mark
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::vector<std::string> w;
    for (std::string s; words >> s;) w.push_back(s);
    if (w.empty()) continue;
    const std::string where = "line " + std::to_string(n);
    ScriptCommand c;
    c.line = n;
    if (!is_number(w[0], c.time_s) || c.time_s < 0)
      throw InputError(file, where, "a time in simulated seconds >= 0 first, found '" + w[0] + "'");
    if (w.size() < 2) throw InputError(file, where, "a command after the time");
    c.name = w[1];
    const auto it = commands().find(c.name);
    if (it == commands().end())
      throw InputError(file, where, "a command (speed, filling, direction, profile, lifter, pause, resume, reset, "
                                    "time_scale, colour, trails, wear, wait_wear, save_scene, save_profiles, "
                                    "screenshot, record, stop_record, report, quit), found '" + c.name + "'");
    c.args.assign(w.begin() + 2, w.end());
    const Shape s = it->second;
    const int na = static_cast<int>(c.args.size());
    if (na < s.min_args || na > s.max_args)
      throw InputError(file, where, c.name + ": " + std::to_string(s.min_args) +
                                        (s.max_args > s.min_args ? "-" + std::to_string(s.max_args) : "") +
                                        " argument(s), found " + std::to_string(na));
    for (int k = 0; k < std::min(na, s.numbers); ++k) {
      double v;
      if (!is_number(c.args[k], v)) throw InputError(file, where, c.name + ": a number, found '" + c.args[k] + "'");
      if (const auto r = ranges().find(c.name); r != ranges().end()) {
        const Range b = r->second;
        if (v < b.lo || v > b.hi || (b.integer && v != std::floor(v))) {
          std::ostringstream e;
          e << c.name << ": " << (b.integer ? "a whole number" : "a number") << " in [" << b.lo << ", " << b.hi
            << "], found '" << c.args[k] << "'";
          throw InputError(file, where, e.str());
        }
      }
    }
    if (c.name == "direction" && c.args[0] != "forward" && c.args[0] != "reverse")
      throw InputError(file, where, "direction: forward or reverse, found '" + c.args[0] + "'");
    if (c.name == "colour" && c.args[0] != "species" && c.args[0] != "speed")
      throw InputError(file, where, "colour: species or speed, found '" + c.args[0] + "'");
    if (c.name == "profile") c.args[0] = (dir / c.args[0]).string();
    out.push_back(c);
  }
  std::stable_sort(out.begin(), out.end(), [](const ScriptCommand& a, const ScriptCommand& b) { return a.time_s < b.time_s; });
  return out;
}

}  // namespace millwear::view
