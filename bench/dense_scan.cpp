// A measured profile as dense as a laser scanner can make it: a drawn lifter and its shell
// plates sampled at POINTS points evenly along the surface, each moved by gauge noise, written
// as the CSV that `millwear profile` and a scene's `[lifters] profile` read.
//
//   build/dense_scan PROFILE POINTS [NOISE_MM] [SEED] > scan.csv
//
// The plates reach half the lifter's base either side, worn 1 mm below the shell line. NOISE_MM (default 0.02) is the standard deviation of
// independent normal noise on both coordinates; SEED (default 1) fixes it. Used to measure
// what a dense scan costs to read and to build a liner from (docs/liner-input.md). Prints
// the CSV; asserts nothing.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <random>
#include <string>

#include "geometry/polyline.hpp"
#include "profiles/profile.hpp"

int main(int argc, char** argv) {
  using namespace millwear;
  if (argc < 3) {
    std::fprintf(stderr, "usage: dense_scan PROFILE POINTS [NOISE_MM] [SEED] > scan.csv\n");
    return 2;
  }
  const long points = std::atol(argv[2]);
  const double noise_mm = argc > 3 ? std::atof(argv[3]) : 0.02;
  const unsigned long seed = argc > 4 ? std::strtoul(argv[4], nullptr, 10) : 1;
  if (points < 3 || !(noise_mm >= 0.0)) {
    std::fprintf(stderr, "dense_scan: expected at least 3 points and a noise >= 0 mm\n");
    return 2;
  }
  LifterProfile profile;
  try {
    profile = load_profile(argv[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dense_scan: %s\n", e.what());
    return 2;
  }
  const Polyline& lifter = profile.points;  // lifter-local metres, feet on y = 0
  const double base = lifter.back().x - lifter.front().x;
  const double plate_y = -1e-3;
  Polyline path{{lifter.front().x - 0.5 * base, plate_y}, {lifter.front().x - 0.02 * base, plate_y}};
  path.insert(path.end(), lifter.begin(), lifter.end());
  path.push_back({lifter.back().x + 0.02 * base, plate_y});
  path.push_back({lifter.back().x + 0.5 * base, plate_y});
  const double total = polyline_length(path);
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_mm);
  std::printf("# %s sampled at %ld points, %.3g mm of gauge noise, seed %lu (bench/dense_scan)\n",
              profile.name.c_str(), points, noise_mm, seed);
  std::printf("x_mm,y_mm\n");
  for (long i = 0; i < points; ++i) {
    const Vec2 p = point_at_length(path, total * static_cast<double>(i) / static_cast<double>(points - 1));
    std::printf("%.5f,%.5f\n", p.x * 1e3 + noise(rng), p.y * 1e3 + noise(rng));
  }
  return 0;
}
