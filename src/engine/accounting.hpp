#pragma once
// Shared accounting of what the contacts do, fed by any backend through ContactRecord:
// per-edge shear work and impact energy on the liner, the torque and power the mill
// draws, energy dissipated in collisions and its spectrum, and the charge's shape.
#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "engine/charge.hpp"
#include "geometry/vec2.hpp"

namespace millwear {

// One contact over one step, in SI units, from either backend.
// The impulse acts on disk a (and its opposite on b, or on the liner edge).
struct ContactRecord {
  int a = -1;               // disk id
  int b = -1;               // other disk id, or -1 for a liner contact
  int edge = -1;            // mill boundary edge id for liner contacts
  Vec2 point_m;             // world contact point
  Vec2 normal;              // unit, from b (or the liner) toward a
  double normal_impulse = 0.0;   // N s, >= 0, on a along normal
  double tangent_impulse = 0.0;  // N s, on a along tangent = left_perp(normal)
  double vn_before = 0.0, vn_after = 0.0;  // relative velocity of a w.r.t. b (or liner)
  double vt_before = 0.0, vt_after = 0.0;  // at the point, m/s, before/after the solve
  std::int64_t step = 0;    // the window's step it acted in (the contact log's; the accounting sets it)
};

struct AccountingOptions {
  bool per_edge = true;             // shear work, impact energy, counts per liner edge
  bool shell_work = true;           // false: shell edges are skipped in per-edge sums
  bool collision_spectrum = false;  // log-binned energy per collision event
  bool charge_shape = true;         // centre of mass, toe and shoulder
  bool contact_log = false;         // keep every liner contact record (bounded, see below)
  bool packed_wear = false;         // packed disks' slip goes into shear_work_J too
  std::size_t contact_log_limit = 200000;  // records kept per window at most
};

// The collision-energy spectrum: 40 log10 bins over the 12 decades from 1e-8 J to 1e4 J
// (10 bins every 3 decades).
constexpr int kSpectrumBins = 40;
constexpr double kSpectrumMinJ = 1e-8;
constexpr double kSpectrumBinsPerDecade = kSpectrumBins / 12.0;
constexpr int kShapeAngleBins = 72;        // 5 deg bins around the mill for toe/shoulder

// Unbroken runs of liner contact per disk id, kept across windows: a disk that touches the
// liner at every step for more than one revolution, its contact staying within 45 deg of
// where the run began in the mill frame, rides round with the mill (packed between lifters,
// or centrifuged), which no disk of a cascading or cataracting charge does. (A disk that
// slides on the shell under a slumping charge touches it all along too, but the shell moves
// under it: its contact sweeps round the mill frame and its run starts again.)
struct LinerStreaks {
  std::vector<std::int64_t> last_step;  // global step of the disk's last liner contact
  std::vector<double> since_s;          // global time its present run of contact began
  std::vector<Vec2> since_dir;          // mill-frame direction of its contact then (unit)
  std::int64_t step = 0;                // global step and time (not reset with the window)
  double clock_s = 0.0;
  double cos_mill = 1.0, sin_mill = 0.0;  // mill angle at the step's start (world -> mill)
};

struct Accounting {
  AccountingOptions options;
  double time_s = 0.0;       // simulated time accumulated
  std::int64_t steps = 0;
  // Liner, per mill boundary edge.
  std::vector<double> shear_work_J;      // sum |Pt * vt_after| (friction times slip): the Archard dw
                                         // (without packed disks' unless options.packed_wear)
  std::vector<double> impact_energy_J;   // normal energy dissipated at the edge
  std::vector<std::uint32_t> contacts;   // contact-steps
  // Mill drive.
  double drive_work_J = 0.0;     // work the mill does on the charge (power * dt)
  double torque_impulse_Nms = 0.0;  // integral of torque on the mill about its axis
  // Dissipation (J), split by where it happens.
  double pp_normal_J = 0.0, pp_tangent_J = 0.0;  // particle-particle
  double pl_normal_J = 0.0, pl_tangent_J = 0.0;  // particle-liner
  double solver_position_J = 0.0;  // potential energy the position correction removed (+)
  double kinetic_J_start = 0.0, kinetic_J_end = 0.0;     // charge KE at window ends
  double potential_J_start = 0.0, potential_J_end = 0.0; // charge PE at window ends
  // Collision events (particle-particle): counts per log bin and energy per bin.
  std::array<double, kSpectrumBins> spectrum_count{};
  std::array<double, kSpectrumBins> spectrum_energy_J{};
  // Charge shape, sampled every step.
  double mass_time_kg_s = 0.0;         // integral of active mass dt
  Vec2 moment_time_kg_m_s;             // integral of sum m x dt (world frame)
  std::array<double, kShapeAngleBins> shell_band_occupancy{};  // area-time near the shell
  double shape_time_s = 0.0;          // time the shape was sampled over
  // Liner contacts of the window, when options.contact_log (memory reserved at reset, so
  // logging does not allocate per contact).
  std::vector<ContactRecord> contact_log;
  double contact_log_time_s = 0.0;     // window time when the log filled up (0: not full)
  // Packing: liner shear work booked by disks in liner contact for over a revolution (a
  // jam's work, whose size follows the contact stiffness: docs/wear-model.md, "Packing"),
  // and disk-steps spent so.
  LinerStreaks streaks;
  double packed_shear_work_J = 0.0;
  std::int64_t packed_disk_steps = 0;
  std::int64_t escaped = 0;            // disks lost through the liner (reported, never silent)
  std::int64_t non_finite = 0;         // disks whose state went NaN/inf
};

// op(x, y) on each field of `to` that sums over steps and the same field of `from` (the
// per-edge arrays over the edges both have): the one list of the sums, for adding windows
// up and taking one from another. The window-end energies, the options, the contact log
// and the packing streaks are not sums; the callers set them.
template <class Op>
void for_each_sum(Accounting& to, const Accounting& from, Op op) {
  const std::size_t edges = std::min(to.shear_work_J.size(), from.shear_work_J.size());
  for (std::size_t e = 0; e < edges; ++e) {
    op(to.shear_work_J[e], from.shear_work_J[e]);
    op(to.impact_energy_J[e], from.impact_energy_J[e]);
    op(to.contacts[e], from.contacts[e]);
  }
  op(to.time_s, from.time_s);
  op(to.steps, from.steps);
  op(to.drive_work_J, from.drive_work_J);
  op(to.torque_impulse_Nms, from.torque_impulse_Nms);
  op(to.pp_normal_J, from.pp_normal_J);
  op(to.pp_tangent_J, from.pp_tangent_J);
  op(to.pl_normal_J, from.pl_normal_J);
  op(to.pl_tangent_J, from.pl_tangent_J);
  op(to.solver_position_J, from.solver_position_J);
  for (int k = 0; k < kSpectrumBins; ++k) {
    op(to.spectrum_count[k], from.spectrum_count[k]);
    op(to.spectrum_energy_J[k], from.spectrum_energy_J[k]);
  }
  op(to.mass_time_kg_s, from.mass_time_kg_s);
  op(to.moment_time_kg_m_s.x, from.moment_time_kg_m_s.x);
  op(to.moment_time_kg_m_s.y, from.moment_time_kg_m_s.y);
  for (int k = 0; k < kShapeAngleBins; ++k) op(to.shell_band_occupancy[k], from.shell_band_occupancy[k]);
  op(to.shape_time_s, from.shape_time_s);
  op(to.packed_shear_work_J, from.packed_shear_work_J);
  op(to.packed_disk_steps, from.packed_disk_steps);
  op(to.escaped, from.escaped);
  op(to.non_finite, from.non_finite);
}

// Reset sums, size per-edge arrays, keep options.
void reset_accounting(Accounting& acc, std::size_t edge_count);

// Add one contact's step. is_shell tells whether the edge belongs to the shell.
// Hot path: no virtual call, and no allocation once warm (the packing streaks grow to the
// largest disk id that has touched the liner; with contact_log, the log up to its limit).
void account_contact(Accounting& acc, const ContactRecord& c, double mill_speed_rad_s,
                     bool edge_is_shell);
// A particle-particle collision event ended with energy_J dissipated in total.
void account_collision_event(Accounting& acc, double energy_J);
// The same in two halves: the event's spectrum bin where it ends (a threaded stage, by
// ranges at once), the booking afterwards in a fixed order. Bin -1: nothing to book.
struct CollisionEvent {
  double energy_J = 0.0;
  int bin = -1;
};
CollisionEvent collision_event(double energy_J);
void account_collision_event(Accounting& acc, const CollisionEvent& event);
// One step's charge-shape sample of disks [i0, i1): their mass, first moment and the shell
// band's occupancy per angle bin (radius^2 x dt_s), for account_step to add.
struct ShapeSample {
  double mass_kg = 0.0;
  Vec2 moment_kg_m;
  std::array<double, kShapeAngleBins> occupancy{};
};
void shape_sample(const ChargeState& s, std::size_t i0, std::size_t i1, double dt_s, double radius_m, double band_m,
                  ShapeSample& out);
// The step's clock and its shape sample (the samples of consecutive disk ranges, added in
// range order: the same bits however many threads took them).
void account_step_samples(Accounting& acc, const ChargeState& s, double dt_s, const ShapeSample* samples,
                          std::size_t count);
// Once per step after the contacts: charge shape sample and time.
void account_step(Accounting& acc, const ChargeState& s, double dt_s, double radius_m,
                  double band_m);

int spectrum_bin(double energy_J);
double spectrum_bin_lower_J(int bin);


}  // namespace millwear
