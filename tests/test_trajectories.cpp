// Flights from the lifters (metrics/trajectories.hpp): the free-flight detector against an
// analytic parabola, the impact shares, the lab mill's impacts at 70% and 90% of critical,
// the same bits for any thread count, and `millwear charge`'s impact and trajectory figures.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include "cli_support.hpp"
#include "common/units.hpp"
#include "engine_fixtures.hpp"
#include "io/csv.hpp"
#include "metrics/trajectories.hpp"
#include "study/charge_run.hpp"
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using millwear::testing::TempDir;
using namespace millwear;

namespace {

constexpr double kG = 9.81;

// A round liner: the shell circle of radius R as a counter-clockwise ring of n vertices.
Polygon round_liner(double radius_m, int n) {
  Polygon ring;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * kPi * k / n;
    ring.push_back({radius_m * std::cos(a), radius_m * std::sin(a)});
  }
  return ring;
}

// One disk's frame.
ChargeState one_disk(Vec2 p, Vec2 v, double t, double omega, double radius_m, double mass_kg) {
  ChargeState s;
  s.position_m = {p};
  s.velocity_m_s = {v};
  s.angle_rad = {0.0};
  s.spin_rad_s = {0.0};
  s.radius_m = {radius_m};
  s.mass_kg = {mass_kg};
  s.species = {0};
  s.active = {1};
  s.time_s = t;
  s.mill_angle_rad = omega * t;
  s.mill_speed_rad_s = omega;
  return s;
}

// World position at angle a (deg from 6 o'clock, counter-clockwise) and radius rho.
Vec2 at_angle(double a_deg, double rho) {
  const double a = a_deg * kPi / 180.0;
  return {rho * std::sin(a), -rho * std::cos(a)};
}

}  // namespace

// A disk carried up the rising side by a mill turning counter-clockwise, released at 130 deg
// from 6 o'clock where the shell no longer holds it (omega^2 rho = g/2 < -g cos 130 deg), flies
// a parabola with no contact and strikes the shell on the falling side. The detector finds
// one flight from the liner, and its impact is the parabola's last free frame: within one
// frame's travel of the analytic intersection with the circle |p| = R - r, on the liner, with
// the energy 1/2 m |v - omega x p|^2 of that frame. At any frame spacing.
TEST(FlightDetector, ABallisticParabolaLandsWhereItMeetsTheShell) {
  const double R = 0.3, r = 0.01, m = 2.0, rho = R - r;
  const double omega = std::sqrt(0.5 * kG / rho);
  const Polygon liner = round_liner(R, 3600);  // chord sag 1e-7 of R: a circle to the tolerance
  const Vec2 gv{0.0, -kG};
  const double release_deg = 130.0;
  for (double dt : {1e-4, 1e-3, 4e-3}) {
    SCOPED_TRACE("frame spacing " + std::to_string(dt));
    // Riding with the mill for 10 frames up to the release at t0.
    const double t0 = 10 * dt;
    const Vec2 p0 = at_angle(release_deg, rho);
    const auto riding = [&](double t) {
      const Vec2 p = rotated(p0, omega * (t - t0));
      return one_disk(p, omega * left_perp(p), t, omega, r, m);
    };
    const Vec2 v0 = omega * left_perp(p0);
    const auto flying = [&](double tau) { return p0 + tau * v0 + (0.5 * tau * tau) * gv; };
    // The analytic landing: the first tau > 0 where |p(tau)| = rho (it starts inward).
    double lo = 1e-6, hi = lo;
    while (length(flying(hi)) < rho) hi += 1e-4;
    lo = hi - 1e-4;
    for (int k = 0; k < 200; ++k) {
      const double mid = 0.5 * (lo + hi);
      (length(flying(mid)) < rho ? lo : hi) = mid;
    }
    const double tau_hit = 0.5 * (lo + hi);
    const Vec2 hit = flying(tau_hit);
    ASSERT_GT(tau_hit, 0.1);  // a real flight across the mill, not a graze

    FlightTracker tracker(liner, riding(0.0));
    for (int k = 1; k <= 10; ++k) tracker.observe(riding(k * dt));
    int k = 1;
    Vec2 last_free = p0, last_v = v0;
    for (; k * dt < tau_hit; ++k) {
      last_free = flying(k * dt);
      last_v = v0 + (k * dt) * gv;
      tracker.observe(one_disk(last_free, last_v, t0 + k * dt, omega, r, m));
    }
    // Struck: on the shell, riding with the mill again.
    for (int j = 0; j < 5; ++j) {
      const Vec2 p = rotated(hit, omega * j * dt);
      tracker.observe(one_disk(p, omega * left_perp(p), t0 + (k + j) * dt, omega, r, m));
    }
    EXPECT_EQ(tracker.launches(), 1u);
    ASSERT_EQ(tracker.impacts().size(), 1u);
    const Impact& im = tracker.impacts()[0];
    EXPECT_NEAR(im.launch_deg, release_deg, 1e-9);
    EXPECT_EQ(im.point_m, last_free);
    // Within one frame's travel at the landing speed (rounding: 1e-12 m).
    const double travel = length(v0 + tau_hit * gv) * dt;
    EXPECT_LE(length(im.point_m - hit), travel + 1e-12);
    EXPECT_NEAR(im.angle_deg, angle_from_bottom_deg(hit, omega), travel / (rho - travel) * 180.0 / kPi + 1e-9);
    EXPECT_LT(im.angle_deg, 0.0);  // on the falling side
    EXPECT_TRUE(im.on_liner);
    const double expected = 0.5 * m * length_sq(last_v - omega * left_perp(last_free));
    EXPECT_NEAR(im.energy_J, expected, 1e-12 * expected);
  }
}

// A disk that leaves the charge in the middle of the mill, or the liner on the falling side,
// flies but not from the lifters: no launch, no impact.
TEST(FlightDetector, FreeRunsThatDoNotStartOnTheRisingLinerAreNotFlights) {
  const double R = 0.3, r = 0.01, m = 1.0, omega = 3.0, dt = 1e-3;
  const Polygon liner = round_liner(R, 720);
  for (const Vec2 start : {Vec2{0.0, 0.0}, at_angle(-60.0, R - r)}) {
    // Held still (a contact cancels gravity) for 3 frames, then free for 20.
    FlightTracker tracker(liner, one_disk(start, {}, 0.0, omega, r, m));
    for (int k = 1; k <= 3; ++k) tracker.observe(one_disk(start, {}, k * dt, omega, r, m));
    for (int k = 1; k <= 20; ++k) {
      const double tau = k * dt;
      tracker.observe(one_disk(start + Vec2{0.0, -0.5 * kG * tau * tau}, {0.0, -kG * tau}, (3 + k) * dt, omega, r, m));
    }
    tracker.observe(one_disk(start, {}, 24 * dt, omega, r, m));
    EXPECT_EQ(tracker.launches(), 0u);
    EXPECT_TRUE(tracker.impacts().empty());
  }
}

// The shares: energy above the toe (outside the bed, from the toe over the top to the
// shoulder) and, of it, what struck the liner; none for a centrifuged charge.
TEST(ImpactShares, EnergyAboveTheToeAndOnTheBareLiner) {
  const auto impact = [](double angle, double energy, bool on_liner, int batch) {
    Impact m;
    m.angle_deg = angle;
    m.energy_J = energy;
    m.on_liner = on_liner;
    m.batch = batch;
    return m;
  };
  // Toe -40, shoulder 60: -100 and 150 are above the toe; -20 lands in the bed.
  const std::vector<Impact> impacts{impact(-100, 2.0, true, 0), impact(-100, 1.0, false, 0),
                                    impact(-20, 1.0, true, 1), impact(150, 4.0, true, 1)};
  const ImpactShares s = impact_shares(impacts, -40.0, 60.0, false);
  EXPECT_EQ(s.impacts, 4u);
  EXPECT_DOUBLE_EQ(s.energy_J, 8.0);
  EXPECT_DOUBLE_EQ(s.above_toe_share, 7.0 / 8.0);
  EXPECT_DOUBLE_EQ(s.liner_share, 6.0 / 8.0);
  EXPECT_DOUBLE_EQ(impact_shares(impacts, -40.0, 60.0, false, 0).liner_share, 2.0 / 3.0);
  EXPECT_TRUE(std::isnan(impact_shares(impacts, -40.0, 60.0, true).liner_share));
  // No toe or shoulder (no disk reached the shell band): no share, where every impact would
  // otherwise count as landing in the bed.
  const double none = std::nan("");
  EXPECT_TRUE(std::isnan(impact_shares(impacts, none, none, false).liner_share));
  EXPECT_TRUE(std::isnan(impact_shares(impacts, none, none, false).above_toe_share));
  const ImpactDistribution d = bin_impacts(impacts, 1);
  EXPECT_DOUBLE_EQ(d.count[16], 2.0);  // -100 deg: bin [-100, -95)
  EXPECT_DOUBLE_EQ(d.liner_energy_J[16], 2.0);
  EXPECT_DOUBLE_EQ(d.species_energy_J[0][66], 4.0);  // 150 deg: bin [150, 155)
}

namespace {

ChargeRunResult lab_at(double speed, int threads) {
  Scene scene = millwear::testing::lab_mill();
  scene.mill.speed_fraction_critical = speed;
  scene.run.revolutions = 4.0;
  scene.solver.threads = threads;
  return run_charge_only(scene);
}

}  // namespace

// The lab mill (draft) at 90% of critical throws its charge further than at 70%: more of
// the flights' impact energy lands above the toe and on the bare liner there. The margins are
// two standard errors of the difference (batch means over the window's sub-windows).
TEST(LabMillImpacts, NinetyPercentOfCriticalPutsMoreImpactEnergyAboveTheToe) {
  const ChargeRunResult slow = lab_at(0.7, 1), fast = lab_at(0.9, 1);
  const auto summary = [](const ChargeRunResult& r) {
    const ChargeSummary& s = r.figures.summary;
    return summarize_impacts(r.impacts, static_cast<int>(r.batches.size()), s.toe_deg, s.shoulder_deg, s.centrifuged);
  };
  const ImpactSummary a = summary(slow), b = summary(fast);
  ASSERT_FALSE(slow.figures.summary.centrifuged);
  ASSERT_FALSE(fast.figures.summary.centrifuged);
  ASSERT_GT(a.window.impacts, 20u);
  ASSERT_GT(b.window.impacts, 20u);
  const double liner_se = std::hypot(a.liner_share.sem, b.liner_share.sem);
  EXPECT_GT(b.window.liner_share - a.window.liner_share, 2.0 * liner_se)
      << "70%: " << a.window.liner_share << " +- " << a.liner_share.sem << ", 90%: " << b.window.liner_share
      << " +- " << b.liner_share.sem;
  const double above_se = std::hypot(a.above_toe_share.sem, b.above_toe_share.sem);
  EXPECT_GT(b.window.above_toe_share - a.window.above_toe_share, 2.0 * above_se)
      << "70%: " << a.window.above_toe_share << " +- " << a.above_toe_share.sem
      << ", 90%: " << b.window.above_toe_share << " +- " << b.above_toe_share.sem;

  // The analysis reads the charge the step leaves, so a second thread changes no bit of it.
  const ChargeRunResult two = lab_at(0.9, 2);
  ASSERT_EQ(two.impacts.size(), fast.impacts.size());
  for (std::size_t i = 0; i < fast.impacts.size(); ++i) {
    ASSERT_EQ(two.impacts[i].disk, fast.impacts[i].disk) << i;
    ASSERT_EQ(two.impacts[i].energy_J, fast.impacts[i].energy_J) << i;
    ASSERT_EQ(two.impacts[i].point_m, fast.impacts[i].point_m) << i;
    ASSERT_EQ(two.impacts[i].on_liner, fast.impacts[i].on_liner) << i;
  }
  ASSERT_EQ(two.flight_paths.size(), fast.flight_paths.size());
}

// `millwear charge` writes impacts.csv, the flight paths and the two figures as PNG and SVG,
// their legends naming each species of the scene (a lab mill of balls and pebbles here).
TEST(AppChargeImpacts, WritesTheImpactAndTrajectoryFiguresNamingTheSpecies) {
  const TempDir dir("millwear-test-impacts");
  std::string text = millwear::testing::read_text(millwear::testing::source_path("scenarios/lab-mill.toml"));
  const auto replace = [&](const std::string& from, const std::string& to) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  };
  replace("\"../profiles/lab-2x30.toml\"", "\"" + millwear::testing::source_path("profiles/lab-2x30.toml") + "\"");
  replace("ball_filling = 0.3", "ball_filling = 0.2");
  text += "\n[[charge.species]]\nname = \"pebble\"\nball = false\ndensity = 2700.0\nsize_range = [15.0, 25.0]\n"
          "friction = 0.5\nrestitution = 0.3\nfriction_liner = 0.5\nrestitution_liner = 0.3\n";
  const fs::path scene = dir / "lab-pebbles.toml";
  std::ofstream(scene) << text;
  const fs::path out = dir / "out";
  const auto r = millwear::testing::run_millwear("charge " + millwear::testing::quoted(scene) + " -o " +
                                                 millwear::testing::quoted(out) + " --revolutions 1 --set mill.speed=0.9");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("flights"), std::string::npos) << r.output;

  const io::CsvData impacts = io::read_csv((out / "impacts.csv").string());
  EXPECT_EQ(impacts.row_count(), static_cast<std::size_t>(kImpactBins));
  for (const char* c : {"impacts_per_s_ball", "impact_power_W_per_m_ball", "impacts_per_s_pebble",
                        "impact_power_W_per_m_pebble", "liner_impact_power_W_per_m"})
    EXPECT_TRUE(impacts.has_column(c)) << c;
  double flights = 0.0;
  for (double v : impacts.numbers("impacts_per_s")) flights += v;
  EXPECT_GT(flights, 0.0);
  const std::string summary = millwear::testing::read_text(out / "charge_summary.csv");
  for (const char* row : {"\nliner_impact_share,", "\nliner_impact_share_se,", "\nimpact_above_toe_share,"})
    EXPECT_NE(summary.find(row), std::string::npos) << row;
  EXPECT_TRUE(fs::exists(out / "trajectories_lab-mill.csv"));

  for (const char* figure : {"impacts_lab-mill", "trajectories_lab-mill"}) {
    const std::string png = millwear::testing::read_text(out / "plots" / (std::string(figure) + ".png"));
    EXPECT_EQ(png.substr(0, 4), "\x89PNG") << figure;
    const std::string svg = millwear::testing::read_text(out / "plots" / (std::string(figure) + ".svg"));
    for (const char* word : {"ball", "pebble", "toe", "shoulder"})
      EXPECT_NE(svg.find(word), std::string::npos) << figure << ": " << word;
  }
}

// A charge run's progress calls follow the settling and then the window through their
// simulated time, and change no step: the figures are the same bits as a run without them.
TEST(ChargeRunProgress, ReportsBothPhasesInOrderAndChangesNothing) {
  Scene scene = millwear::testing::lab_mill();
  scene.run.revolutions = 1.0;
  std::vector<ChargeProgress> seen;
  const ChargeRunResult with = run_charge_only(scene, [&](const ChargeProgress& p) { seen.push_back(p); });
  const ChargeRunResult without = run_charge_only(scene);
  ASSERT_FALSE(seen.empty());
  EXPECT_STREQ(seen.front().phase, "settling");
  EXPECT_STREQ(seen.back().phase, "measuring");
  for (std::size_t i = 1; i < seen.size(); ++i) {
    if (std::string(seen[i].phase) != seen[i - 1].phase) {
      EXPECT_STREQ(seen[i - 1].phase, "settling");  // one change, settling to measuring
      continue;
    }
    EXPECT_GT(seen[i].done_s, seen[i - 1].done_s) << i;
    EXPECT_LE(seen[i].done_s, seen[i].of_s) << i;
  }
  EXPECT_EQ(with.figures.power_kW_per_m, without.figures.power_kW_per_m);
  ASSERT_EQ(with.final_state.position_m.size(), without.final_state.position_m.size());
  for (std::size_t i = 0; i < with.final_state.position_m.size(); ++i) {
    EXPECT_EQ(with.final_state.position_m[i], without.final_state.position_m[i]) << i;
    EXPECT_EQ(with.final_state.velocity_m_s[i], without.final_state.velocity_m_s[i]) << i;
  }
  EXPECT_EQ(with.impacts.size(), without.impacts.size());
}
