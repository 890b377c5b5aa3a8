// The shared contact accounting, record by record (no engine).
#include <cmath>

#include <gtest/gtest.h>

#include "common/units.hpp"
#include "engine/accounting.hpp"
#include "metrics/charge_summary.hpp"

namespace millwear {
namespace {

ContactRecord liner_contact() {
  ContactRecord c;
  c.a = 0;
  c.b = -1;
  c.edge = 2;
  c.point_m = {0.0, -1.0};  // at the bottom of a 1 m mill
  c.normal = {0.0, 1.0};    // from the liner toward the disk
  c.normal_impulse = 2.0;
  c.tangent_impulse = -0.5;  // along left_perp(normal) = (-1, 0): i.e. +0.5 N s toward +x
  c.vn_before = -1.0;
  c.vn_after = 0.0;
  c.vt_before = 0.4;
  c.vt_after = 0.2;
  return c;
}

TEST(Accounting, LinerContactGivesShearWorkImpactEnergyAndTorque) {
  Accounting acc;
  acc.options.per_edge = true;
  reset_accounting(acc, 4);
  account_contact(acc, liner_contact(), 1.0, false);
  // Shear work |Pt * vt_after| = 0.5 * 0.2.
  EXPECT_DOUBLE_EQ(acc.shear_work_J[2], 0.1);
  // Normal loss -Pn * mean(vn) = -2 * (-0.5) = 1 J.
  EXPECT_DOUBLE_EQ(acc.impact_energy_J[2], 1.0);
  EXPECT_DOUBLE_EQ(acc.pl_normal_J, 1.0);
  // Tangential loss -Pt * mean(vt) = 0.5 * 0.3.
  EXPECT_DOUBLE_EQ(acc.pl_tangent_J, 0.15);
  // Impulse on the disk (0.5, 2) at (0, -1): torque r x P = 0 * 2 - (-1) * 0.5 = 0.5 N m s,
  // and with omega = 1 the drive did 0.5 J.
  EXPECT_DOUBLE_EQ(acc.torque_impulse_Nms, 0.5);
  EXPECT_DOUBLE_EQ(acc.drive_work_J, 0.5);
  EXPECT_EQ(acc.contacts[2], 1u);
}

// One step of a 1 rad/s mill (a revolution is 2 pi s) in steps of 0.1 s, with disk 0 on
// the liner when `touching`. The state's mill angle stays 0, so the contact point stays put
// in the mill frame: the disk rides with the liner.
void liner_step(Accounting& acc, bool touching, double omega = 1.0) {
  if (touching) account_contact(acc, liner_contact(), omega, false);
  account_step(acc, ChargeState{}, 0.1, 1.0, 0.1);
}

TEST(Accounting, ADiskOnTheLinerForOverARevolutionIsPackedAndItsShearWorkIsCounted) {
  Accounting acc;
  acc.options.charge_shape = false;
  reset_accounting(acc, 4);
  // Steps 0..62 end at 6.3 s, but the run began at step 0: 6.2 s of contact < 2 pi.
  for (int k = 0; k < 63; ++k) liner_step(acc, true);
  EXPECT_EQ(acc.packed_shear_work_J, 0.0);
  EXPECT_EQ(acc.packed_disk_steps, 0);
  // Step 63: 6.3 s > 2 pi since its run began. The disk touches two edges in it: both
  // contacts' work counts, the disk-step once.
  account_contact(acc, liner_contact(), 1.0, false);
  EXPECT_DOUBLE_EQ(acc.packed_shear_work_J, 0.1);
  account_contact(acc, liner_contact(), 1.0, false);
  account_step(acc, ChargeState{}, 0.1, 1.0, 0.1);
  EXPECT_DOUBLE_EQ(acc.packed_shear_work_J, 0.2);
  EXPECT_EQ(acc.packed_disk_steps, 1);
  const ChargeSummary s = summarize(acc, 1.0, 9.81);
  EXPECT_NEAR(s.packed_shear_share, 0.2 / (0.1 * 65), 1e-12);
  EXPECT_DOUBLE_EQ(s.mean_packed_disks, 1.0 / 64);
}

TEST(Accounting, APackedRunSurvivesTheWindowResetAndEndsWhenTheDiskLeavesTheLiner) {
  Accounting acc;
  acc.options.charge_shape = false;
  reset_accounting(acc, 4);
  for (int k = 0; k < 40; ++k) liner_step(acc, true);
  reset_accounting(acc, 4);  // a new window: the disk's run of contact goes on
  for (int k = 0; k < 24; ++k) liner_step(acc, true);
  EXPECT_GT(acc.packed_shear_work_J, 0.0);
  liner_step(acc, false);  // one step off the liner ends the run
  const double before = acc.packed_shear_work_J;
  for (int k = 0; k < 60; ++k) liner_step(acc, true);
  EXPECT_EQ(acc.packed_shear_work_J, before);
}

TEST(Accounting, ADiskSlidingOnTheTurningShellIsNotPacked) {
  // The contact stays at the bottom of the world while the mill turns under it (a slumping
  // charge's bottom layer): in the mill frame it sweeps round, so its run of contact keeps
  // starting again, and its slip is wear.
  Accounting acc;
  acc.options.charge_shape = false;
  reset_accounting(acc, 4);
  ChargeState turning;
  for (int k = 0; k < 200; ++k) {  // 20 s: over three revolutions
    account_contact(acc, liner_contact(), 1.0, false);
    turning.mill_angle_rad += 0.1;
    account_step(acc, turning, 0.1, 1.0, 0.1);
  }
  EXPECT_EQ(acc.packed_shear_work_J, 0.0);
  EXPECT_EQ(acc.packed_disk_steps, 0);
  EXPECT_DOUBLE_EQ(acc.shear_work_J[2], 200 * 0.1);
}

TEST(Accounting, NothingIsPackedInAMillAtRest) {
  Accounting acc;
  acc.options.charge_shape = false;
  reset_accounting(acc, 4);
  for (int k = 0; k < 200; ++k) liner_step(acc, true, 0.0);
  EXPECT_EQ(acc.packed_shear_work_J, 0.0);
  EXPECT_EQ(acc.packed_disk_steps, 0);
}

TEST(Accounting, ShellWorkIsSkippedWhenNotAskedFor) {
  Accounting acc;
  acc.options.shell_work = false;
  reset_accounting(acc, 4);
  account_contact(acc, liner_contact(), 1.0, true);
  EXPECT_EQ(acc.shear_work_J[2], 0.0);
  EXPECT_DOUBLE_EQ(acc.drive_work_J, 0.5);  // the drive still pays for it
}

TEST(Accounting, ParticleContactsCountAsCollisionsNotLinerWork) {
  Accounting acc;
  reset_accounting(acc, 4);
  ContactRecord c = liner_contact();
  c.b = 1;
  account_contact(acc, c, 1.0, false);
  EXPECT_DOUBLE_EQ(acc.pp_normal_J, 1.0);
  EXPECT_DOUBLE_EQ(acc.pp_tangent_J, 0.15);
  EXPECT_EQ(acc.drive_work_J, 0.0);
  for (double w : acc.shear_work_J) EXPECT_EQ(w, 0.0);
}

TEST(Accounting, SpectrumBinsAreLogarithmic) {
  EXPECT_EQ(spectrum_bin(kSpectrumMinJ * 0.5), 0);
  const int b = spectrum_bin(1.0);
  EXPECT_LE(spectrum_bin_lower_J(b), 1.0);
  EXPECT_GT(spectrum_bin_lower_J(b + 1), 1.0);
  Accounting acc;
  account_collision_event(acc, 1.0);
  account_collision_event(acc, 1.0);
  EXPECT_EQ(acc.spectrum_count[b], 2.0);
  EXPECT_DOUBLE_EQ(acc.spectrum_energy_J[b], 2.0);
}

TEST(Accounting, ContactLogKeepsLinerContactsUpToItsLimit) {
  Accounting acc;
  acc.options.contact_log = true;
  acc.options.contact_log_limit = 3;
  reset_accounting(acc, 4);
  for (int k = 0; k < 5; ++k) account_contact(acc, liner_contact(), 1.0, false);
  EXPECT_EQ(acc.contact_log.size(), 3u);
  EXPECT_EQ(acc.contact_log[0].edge, 2);
  Accounting off;
  reset_accounting(off, 4);
  account_contact(off, liner_contact(), 1.0, false);
  EXPECT_TRUE(off.contact_log.empty());
}

// A bed filling the bottom of the shell band from 60 deg on the falling side to 120 deg on the
// rising side (5 deg bins, bin k covers [5k, 5k+5) deg counter-clockwise from 6 o'clock).
Accounting bed_occupancy(double outside) {
  Accounting acc;
  for (int k = 0; k < kShapeAngleBins; ++k) {
    const double lo = 5.0 * k;
    const bool rising = lo < 120.0, falling = lo >= 300.0;
    acc.shell_band_occupancy[k] = (rising || falling) ? 1.0 : outside;
  }
  acc.time_s = 1.0;
  return acc;
}

TEST(ChargeShape, ABedHasItsToeAndShoulderWhereTheBandEmpties) {
  // An empty band outside the bed: half the bed's value is crossed half-way between the
  // centres of the last full bin and the first empty one, on the bed's edge.
  ChargeSummary s = summarize(bed_occupancy(0.0), 1.0, 9.81);
  EXPECT_FALSE(s.centrifuged);
  EXPECT_DOUBLE_EQ(s.shoulder_deg, 120.0);
  EXPECT_DOUBLE_EQ(s.toe_deg, -60.0);
  // A thin layer of 0.1 outside: occupancy linear between bin centres 117.5 and 122.5 deg
  // (1 to 0.1) crosses 0.5 at 117.5 + 5 x 0.5 / 0.9 deg; the toe likewise below -57.5 deg.
  s = summarize(bed_occupancy(0.1), 1.0, 9.81);
  EXPECT_NEAR(s.shoulder_deg, 117.5 + 5.0 * 0.5 / 0.9, 1e-12);
  EXPECT_NEAR(s.toe_deg, -(57.5 + 5.0 * 0.5 / 0.9), 1e-12);
}

TEST(ChargeShape, TheEdgeMovesContinuouslyWithTheOccupancy) {
  // The first bin past the bed filling from 0 to just under half: the shoulder moves from the
  // bed's edge toward the next bin's centre, never jumping a bin.
  double last = 0.0;
  for (double f : {0.0, 0.1, 0.2, 0.3, 0.4, 0.45, 0.49}) {
    Accounting acc = bed_occupancy(0.0);
    acc.shell_band_occupancy[24] = f;  // [120, 125) deg, rising side
    const double shoulder = summarize(acc, 1.0, 9.81).shoulder_deg;
    EXPECT_NEAR(shoulder, 117.5 + 5.0 * 0.5 / (1.0 - f), 1e-12) << f;
    EXPECT_GT(shoulder, last) << f;
    EXPECT_LT(shoulder, 122.5) << f;
    last = shoulder;
  }
}

TEST(ChargeShape, TheRisingSideFollowsTheDirectionOfRotation) {
  // Turning clockwise, the side at negative angles rises: the same bed reads mirrored.
  const ChargeSummary s = summarize(bed_occupancy(0.0), -1.0, 9.81);
  EXPECT_DOUBLE_EQ(s.shoulder_deg, 60.0);
  EXPECT_DOUBLE_EQ(s.toe_deg, -120.0);
}

TEST(ChargeShape, ABedOffTheBottomIsWalkedFromItsFullestBin) {
  // Solids from 20 to 120 deg up the rising side and none at 6 o'clock: the bed rode up the
  // shell. Its edges are those of the run around the fullest bin, the toe on the rising side.
  Accounting acc;
  acc.time_s = 1.0;
  for (int k = 4; k < 24; ++k) acc.shell_band_occupancy[k] = 0.8;
  acc.shell_band_occupancy[10] = 1.0;  // the fullest bin: half of it is 0.5
  // 0.8 at the centres of the bed's end bins (22.5 and 117.5 deg), 0 at the next ones': half
  // of the peak is crossed 5 x 0.3 / 0.8 deg beyond.
  const double beyond = 5.0 * 0.3 / 0.8;
  ChargeSummary s = summarize(acc, 1.0, 9.81);
  EXPECT_FALSE(s.centrifuged);
  EXPECT_NEAR(s.shoulder_deg, 117.5 + beyond, 1e-12);
  EXPECT_NEAR(s.toe_deg, 22.5 - beyond, 1e-12);
  // Turning the other way the same bed sits on the falling side.
  s = summarize(acc, -1.0, 9.81);
  EXPECT_NEAR(s.shoulder_deg, -(22.5 - beyond), 1e-12);
  EXPECT_NEAR(s.toe_deg, -(117.5 + beyond), 1e-12);
  // Across 180 deg (from 150 to 210 deg): the angles stay in (-180, 180].
  acc.shell_band_occupancy.fill(0.0);
  for (int k = 30; k < 42; ++k) acc.shell_band_occupancy[k] = 1.0;
  s = summarize(acc, 1.0, 9.81);
  EXPECT_NEAR(s.toe_deg, 150.0, 1e-12);
  EXPECT_NEAR(s.shoulder_deg, -150.0, 1e-12);
}

TEST(ChargeShape, AWindowInWhichNoDiskReachedTheBandHasNoToeOrShoulder) {
  Accounting acc;
  acc.time_s = 1.0;
  const ChargeSummary s = summarize(acc, 1.0, 9.81);
  EXPECT_TRUE(std::isnan(s.toe_deg));
  EXPECT_TRUE(std::isnan(s.shoulder_deg));
  EXPECT_FALSE(s.centrifuged);
}

TEST(ChargeShape, ABandFullAllRoundIsCentrifuged) {
  // Over half the bed's value in every bin: the charge rides the whole shell.
  const ChargeSummary s = summarize(bed_occupancy(0.6), 1.0, 9.81);
  EXPECT_TRUE(s.centrifuged);
  // Just under half somewhere is a bed again.
  EXPECT_FALSE(summarize(bed_occupancy(0.49), 1.0, 9.81).centrifuged);
}

TEST(ChargeShape, TheCentreOfMassAngleIsMeasuredFrom6OClockTowardTheRisingSide) {
  Accounting acc;
  acc.time_s = 1.0;
  acc.shape_time_s = 1.0;
  acc.mass_time_kg_s = 2.0;
  acc.moment_time_kg_m_s = {2.0 * 0.1, -2.0 * 0.1};  // at (0.1, -0.1): 45 deg up the +x side
  EXPECT_NEAR(summarize(acc, 1.0, 9.81).centre_of_mass_deg, 45.0, 1e-12);
  EXPECT_NEAR(summarize(acc, -1.0, 9.81).centre_of_mass_deg, -45.0, 1e-12);
}

// A 0.1 m slice of a 5 m mill: 50 slices. 200 kg and 30 kW a slice are 10 t and 1.5 MW a
// mill, 150 kW/t. A liner losing 2e-9 m^2 of cross-section a second along 5 m of steel
// (7800 kg/m^3) loses 7.8e-5 kg/s: 7.8e-5 / 1.5e6 kg/J = 0.1872 g/kWh.
// A window is sound when its disk-disk contacts dissipate and its books close: the drive's
// power less the dissipation booked and the charge's energy change within a tenth of it.
TEST(ChargeEnergy, AWindowIsUnsoundWhenCollisionsGiveEnergyOrTheBooksDoNotClose) {
  ChargeFigures f;
  f.summary.power_W = 1000.0;
  f.summary.collision_power_W = 700.0;
  f.summary.liner_dissipation_W = 250.0;
  f.summary.solver_dissipation_W = 20.0;
  f.summary.kinetic_change_W = -20.0;  // 50 W (5%) unbooked
  f.collision_kW_per_m = 0.7;
  f.power_kW_per_m = 1.0;
  EXPECT_EQ(unsound_energy_split(f), "");
  f.summary.liner_dissipation_W = 150.0;  // 150 W (15%) unbooked
  EXPECT_NE(unsound_energy_split(f).find("do not close"), std::string::npos) << unsound_energy_split(f);
  EXPECT_NE(unsound_energy_split(f).find("15% of the drive's power"), std::string::npos) << unsound_energy_split(f);
  f.summary.liner_dissipation_W = 350.0;  // 50 W (-5%) booked beyond the work
  EXPECT_EQ(unsound_energy_split(f), "");
  f.summary.collision_power_W = -100.0;   // closes, yet the collisions gave energy
  f.summary.liner_dissipation_W = 1100.0;
  f.collision_kW_per_m = -0.1;
  EXPECT_NE(unsound_energy_split(f).find("gave the charge energy"), std::string::npos) << unsound_energy_split(f);
  f.summary.power_W = 0.0;                // a mill at rest draws nothing: only the collisions judge
  f.summary.collision_power_W = f.summary.liner_dissipation_W = f.summary.solver_dissipation_W = 0.0;
  f.summary.kinetic_change_W = -5.0;
  f.collision_kW_per_m = 0.0;
  EXPECT_EQ(unsound_energy_split(f), "");
}

// A window is unsteady when the charge's energy changes by more than a tenth of the drive's
// power either way; a charge losing energy was said to take in a negative share of the power.
TEST(ChargeEnergy, AnUnsteadyWindowSaysWhichWayTheChargesEnergyWent) {
  ChargeSummary s;
  s.power_W = 1000.0;
  s.kinetic_change_W = 50.0;
  EXPECT_EQ(unsteady_window(s), "");
  s.kinetic_change_W = 130.0;
  EXPECT_NE(unsteady_window(s).find("13% of the drive's power went into its kinetic and potential energy"),
            std::string::npos) << unsteady_window(s);
  s.kinetic_change_W = -890.0;
  EXPECT_NE(unsteady_window(s).find("its kinetic and potential energy fell by 89% of the drive's power"),
            std::string::npos) << unsteady_window(s);
  EXPECT_EQ(unsteady_window(s).find("-89"), std::string::npos) << unsteady_window(s);
}

TEST(MillEnergy, SliceFiguresScaleToTheMillAndSetLinerLossAgainstEnergy) {
  ChargeSummary s;
  s.mass_kg = 200.0;
  s.power_W = 30e3;
  const MillEnergyFigures f = mill_energy_figures(s, 0.1, 5.0, 2e-9, 7800.0);
  EXPECT_NEAR(f.charge_mass_kg, 1e4, 1e-9);
  EXPECT_NEAR(f.power_W, 1.5e6, 1e-6);
  EXPECT_NEAR(kW_per_t(f.specific_power_W_per_kg), 150.0, 1e-12);
  EXPECT_NEAR(g_per_kWh(f.liner_wear_kg_per_J), 0.1872, 1e-12);
}

}  // namespace
}  // namespace millwear
