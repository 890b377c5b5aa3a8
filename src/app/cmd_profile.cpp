// `millwear profile FILE... [--csv DIR]`: read lifter profile files, print their metrics as a
// table (mm, mm^2, degrees), and optionally write each polyline as DIR/<name>.csv.
// Every file is read and validated before anything is printed or written.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "app/commands.hpp"
#include "app/output_folder.hpp"
#include "common/units.hpp"
#include "profiles/profile.hpp"

namespace millwear::app {

namespace {


struct ProfileArgs {
  std::vector<std::string> files;
  std::string csv_dir;
};

int run_profile(const ProfileArgs& args) {
  std::vector<LifterProfile> profiles;
  for (const std::string& f : args.files) profiles.push_back(load_profile(f));

  // --csv: every file it would write checked before anything is printed or written.
  if (!args.csv_dir.empty()) check_profile_csv_targets(profiles, args.csv_dir);

  char row[256];
  std::snprintf(row, sizeof row, "%-16s %12s %10s %10s %10s %10s %10s\n", "name", "area_mm2",
                "height_mm", "base_mm", "top_mm", "lead_deg", "trail_deg");
  std::cout << row;
  for (const LifterProfile& p : profiles) {
    const ProfileMetrics m = measure_profile(p.points);
    std::snprintf(row, sizeof row, "%-16s %12.1f %10.1f %10.1f %10.1f %10.1f %10.1f\n",
                  p.name.c_str(), in_mm2(m.area_m2), in_mm(m.height_m), in_mm(m.base_width_m),
                  in_mm(m.top_width_m), deg_from_rad(m.leading_face_angle_rad),
                  deg_from_rad(m.trailing_face_angle_rad));
    std::cout << row;
  }
  // Measured profiles: what was read, and what lies outside the lifter.
  for (const LifterProfile& p : profiles) {
    if (p.measured.empty()) continue;
    double lowest = 0.0, left = p.measured.front().x, right = left;
    for (const Vec2& v : p.measured) {
      lowest = std::min(lowest, v.y);
      left = std::min(left, v.x), right = std::max(right, v.x);
    }
    std::snprintf(row, sizeof row,
                  "%s: measured surface of %zu points (%d repeated or looping dropped), x from %.1f to %.1f mm, "
                  "lowest y %.1f mm; the lifter is its part above y = 0\n",
                  p.name.c_str(), p.measured.size(), p.dropped_points, left * 1e3, right * 1e3, lowest * 1e3);
    std::cout << row;
    if (p.unit_pitch_m > 0.0) {
      std::snprintf(row, sizeof row, "%s: one whole liner unit, pitch %.1f mm (line %d)\n", p.name.c_str(),
                    in_mm(p.unit_pitch_m), p.pitch_line);
      std::cout << row;
    }
  }

  if (!args.csv_dir.empty()) write_profile_csvs(profiles, args.csv_dir);
  return 0;
}

}  // namespace

void register_profile(CLI::App& app, Action* action) {
  auto args = std::make_shared<ProfileArgs>();
  CLI::App* sub = app.add_subcommand(
      "profile", "Print lifter profile metrics (area, height, widths, face angles)");
  sub->add_option("files", args->files, "Profile files (TOML, or measured x_mm,y_mm CSV)")->required();
  sub->add_option("--csv", args->csv_dir, "Write each profile's polyline to DIR/<name>.csv (mm)")
      ->check(output_folder());
  sub->callback([args, action] { *action = [args] { return run_profile(*args); }; });
}

}  // namespace millwear::app
