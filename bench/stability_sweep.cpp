// Stability sweep: the tiny mill of the stability suite (tests/stability_run.hpp) beyond
// and inside every limit, printed as tables for docs/stability.md. Runs with the limit
// checks off (guarded = false) so it shows what happens past them. Asserts nothing.
//   build/stability_sweep [time_step|soft_step|speed|filling|size_ratio|restitution|friction|all]
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "../tests/stability_run.hpp"

using namespace millwear;
using namespace millwear::stability;

namespace {

void line(const std::string& label, const Scene& s, const Outcome& o) {
  std::printf("%-34s disks %5zu  travel %5.2f r  escaped %4lld  non-finite %3lld  max speed %6.2f m/s (bound %5.2f)%s\n",
              label.c_str(), o.disks, step_travel_radii(s), o.escaped, o.non_finite, o.max_speed_m_s,
              o.speed_bound_m_s, o.completed ? "" : ("  STOPPED: " + o.error).c_str());
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  const std::string what = argc > 1 ? argv[1] : "all";
  const bool all = what == "all";
  if (all || what == "time_step") {
    std::printf("# time step against particle size (tiny mill, 75%% critical, 1 revolution)\n");
    for (double d : {6.0, 15.0, 40.0})
      for (double hz : {5000.0, 2000.0, 1000.0, 500.0, 240.0, 120.0, 60.0}) {
        if (d < 10.0 && hz > 2500.0) continue;  // slow and far inside the limit
        Scene s = tiny_mill(d, 1.67, 0.2);
        s.solver.time_step_s = 1.0 / hz;
        char label[64];
        std::snprintf(label, sizeof label, "d_min %4.0f mm, dt 1/%-5.0f", d, hz);
        line(label, s, run_briefly(s, 1.0, false));
      }
  }
  if (all || what == "soft_step") {
    // The soft backend's step, held to 1.2 radii per substep (inside kMaxStepTravelRadii)
    // and to 64 substeps, so that only the travel per step grows.
    std::printf("# soft step: radii per step at the impact speed (tiny mill, 15 mm, 3 revolutions)\n");
    for (double radii : {6.0, 8.0, 10.0, 12.5, 15.0, 20.0})
      for (int substeps : {static_cast<int>(std::ceil(radii / 1.2)), 64})
        for (std::uint64_t seed : {1, 2, 3}) {
          Scene s = tiny_mill(15.0, 1.67, 0.2);
          s.solver.backend = Backend::Soft;
          s.solver.substeps = substeps;
          s.solver.seed = seed;
          s.solver.time_step_s = radii * s.smallest_particle_radius_m() / impact_speed_m_s(s);
          char label[64];
          std::snprintf(label, sizeof label, "%4.1f r/step, %2d substeps, seed %d", radii, substeps, static_cast<int>(seed));
          line(label, s, run_briefly(s, 3.0, false));
        }
  }
  if (all || what == "speed") {
    std::printf("# mill speed (fraction of critical), dt 1/1000\n");
    for (double f : {0.0, 0.3, 0.75, 1.0, 1.3, 1.6}) {
      Scene s = tiny_mill();
      s.mill.speed_fraction_critical = f;
      line("speed " + std::to_string(f), s, run_briefly(s, 2.0, false));
    }
  }
  if (all || what == "filling") {
    std::printf("# filling, dt 1/1000\n");
    for (double f : {0.0, 1e-4, 0.01, 0.1, 0.3, 0.5}) {
      Scene s = tiny_mill(15.0, 1.67, f);
      line("filling " + std::to_string(f), s, run_briefly(s, 1.0, false));
    }
  }
  if (all || what == "size_ratio") {
    std::printf("# size ratio (d_max / d_min, d_min 8 mm), dt 1/1000\n");
    for (double q : {1.0, 2.0, 4.0, 6.0, 10.0}) {
      Scene s = tiny_mill(q >= 4.0 ? 5.0 : 8.0, q, 0.2);
      line("ratio " + std::to_string(q), s, run_briefly(s, 1.0, false));
    }
  }
  if (all || what == "restitution") {
    std::printf("# restitution (particle and liner), dt 1/1000\n");
    for (double e : {0.0, 0.3, 0.6, 0.8, 0.95}) {
      Scene s = tiny_mill();
      for (auto& sp : s.charge.species) sp.restitution = sp.restitution_liner = e;
      line("restitution " + std::to_string(e), s, run_briefly(s, 2.0, false));
    }
  }
  if (all || what == "friction") {
    std::printf("# friction (particle and liner), dt 1/1000\n");
    for (double mu : {0.0, 0.1, 0.5, 1.0}) {
      Scene s = tiny_mill();
      for (auto& sp : s.charge.species) sp.friction = sp.friction_liner = mu;
      line("friction " + std::to_string(mu), s, run_briefly(s, 2.0, false));
    }
  }
  return 0;
}
