#pragma once
// The end of a soft step: the solver's disks written back to the ChargeState by id, with
// the checks MuJoCo makes inside its step (a non-finite disk, a disk escaped through the
// shell or leaked into the liner is removed and reported where it arises), and every
// contact fed once to the shared accounting with its impulses summed over the substeps.
//
// Energy. With anchors and directions fixed for the step, every disk's velocity change is
// exactly gravity * dt plus the sum of its contact impulses / mass, so its kinetic energy
// changes by exactly (m g dt + sum P) . (v_before + v_after) / 2, "before" the step's start
// velocity. The impulses' share, summed over contacts as P . (v_rel before + v_rel after) / 2
// (the liner's velocity taken out of v_rel: its part is the drive's work), is split per
// contact without residue. Rolling resistance couples are accounted in the same way (added to the
// tangential dissipation, and through the liner to the drive torque).
#include <cstdint>
#include <vector>

#include "engine/accounting.hpp"
#include "engine/charge.hpp"
#include "engine/engine.hpp"
#include "engine/soft/contact_set.hpp"
#include "engine/soft/disks.hpp"
#include "engine/soft/model.hpp"
#include "engine/soft/workers.hpp"

namespace millwear::soft {

// Where the ChargeState and the events of the engine are reported to.
struct Report {
  ChargeState& charge;
  Accounting& accounting;
  std::vector<EngineEvent>& events;
};

// Scratch of the threaded finish: per range, partial sums (added in range order, so the
// totals do not depend on the thread count) and the collision events that ended; per disk,
// what the check found.
struct FinishScratch {
  struct PairSums {
    double normal_J = 0, tangent_J = 0;
    std::size_t ended = 0;           // events ended, at the front of ended_events
    std::vector<CollisionEvent> ended_events;
    std::vector<std::uint32_t> acted, idle;  // the range's rows that carried an impulse, and not
  };
  std::vector<PairSums> pairs;       // per range of disk-pair contacts
  std::vector<double> position_J;    // per range of disks: the solver's position correction
  std::vector<std::uint8_t> flagged; // per range of disks: some disk to remove
  std::vector<std::uint8_t> verdict; // per disk: 0 kept, 1 non-finite, 2 escaped (the write-back);
                                     // 0 kept, 1 leaked (the liner check)
};

// Positions, velocities, angles and spins back to the charge by id; the solver's position
// correction into the energy balance; non-finite and escaped disks removed (in disk order,
// after the ranges ran).
void write_back_and_check(const Model& model, const LinerModel& liner, const StepStart& start,
                          Disks& disks, Report report, FinishScratch& scratch,
                          Workers& workers);

// Every contact that carried an impulse this step to the accounting; collision events
// closed for the spectrum. Disk pairs in ranges, their dissipation summed directly (partial
// sums added in range order); the liner contacts in order, on one thread, each as a
// ContactRecord (per-edge sums and packing streaks).
void account_contacts(const LinerModel& liner, const Disks& disks, const StepStart& start,
                      double mill_speed_rad_s, Contacts& contacts, Accounting& accounting,
                      FinishScratch& scratch, Workers& workers);

// The step's time and the mill's turn.
void advance_clock(const Model& model, ChargeState& charge);

inline bool inside_liner_check_due(std::int64_t step) {
  return step % kInsideLinerCheckInterval == 0;
}
// Disks whose centre got deeper into the lifter metal than the liner contacts reach are
// removed as leaked.
void check_inside_liner(const Model& model, const LinerModel& liner, Disks& disks,
                        Report report, FinishScratch& scratch, Workers& workers);

}  // namespace millwear::soft
