#pragma once
// The contact solver of the soft backend, after Box2D v3's soft step: per substep
// integrate velocities (gravity), warm start, soft solve, integrate positions, relax; once
// per step, restitution. Friction is bounded by mu times the normal impulse, rolling
// resistance by its lever times it.
//
// Soft contact. A penetrating contact is an implicit spring-damper of frequency f and
// damping ratio zeta solved at the substep h (Softness, model.hpp):
//   d_lambda = -m_n * mass_scale * (vn + max(bias_rate * s, -push_out)) - impulse_scale * lambda.
// The relax pass solves the same rows rigidly with no bias, which takes out the velocity
// the bias added (the position it pushed stays pushed): the energy that bias puts in or
// takes out shows up only as the position correction, reported in solver_position_J.
// A contact still apart (s > 0) is speculative: it allows the disks to close exactly the
// gap this substep (bias s / h) and no more, which is what stops tunnelling.
//
// Order. The disk-pair rows live at the start of a step (they carried an impulse out of
// the last one: a third of the pairs, and nearly all that act in a pass) are coloured and
// solved four at a time in vector lanes (colour_solve.hpp); the serial passes keep the rest,
// with their skip of inert rows and lazy building. In the solve and the relax the serial rows
// go first, then the colours in order, then the liner contacts (last, so that they win: the
// liner must not be pushed through); the warm start applies the colours' impulses, then the
// live serial rows', then the liner's.
//
// Threads (workers.hpp). The disks are cut into blocks of a fixed size (broad_phase.hpp:
// from the positions, never from the thread count), and the serial rows are listed by the
// block of their lower disk a in three phases: rows whose disks are both in that block
// (the blocks run at once), rows reaching into the next block (even blocks at once, then
// odd ones: two such rows of one parity never share a disk), and the few reaching further
// (one after another). Within a list, key order. The inside rows and the even blocks'
// next rows share a stage: a range takes two blocks, their inside rows, then the rows from
// the first into the second. The chunks of one colour share no disk and run at once; the
// liner rows run in the disk stages' ranges of their disks. Every Gauss-Seidel order is
// therefore fixed by the contact list and the block size alone: the bits are the same for
// any thread count, run to run, and with four (AVX2) or two (SSE2) lanes per register.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/soft/colour_solve.hpp"
#include "engine/soft/contact_set.hpp"
#include "engine/soft/disks.hpp"
#include "engine/soft/model.hpp"
#include "engine/soft/workers.hpp"

namespace millwear::soft {

// The serial rows' phases (see "Threads" above).
enum Phase { kInside = 0, kNext = 1, kFar = 2, kPhases = 3 };

// Which disk-pair rows are solved how, this step.
struct SolverRows {
  ColouredRows coloured;          // the live rows that found a colour, in lanes
  // Blocks of block_disks disks; block k's rows (lower disk in it) are contacts
  // [first[k], first[k + 1]) of the key-ordered list.
  int block_disks = 1, blocks = 0;
  std::vector<std::size_t> first;
  // Per phase, the serial rows of block k at list[p][first[k] ..], n[p][k] of them; and
  // the live ones among them for the warm start (set by the colouring for the first
  // substep and by each relax for the next), at warm[p][first[k] ..], warm_n[p][k].
  std::vector<int> list[kPhases], warm[kPhases];
  std::vector<int> n[kPhases], warm_n[kPhases];
  // The listed rows' gaps, copied in list order, block k's phases one after the other from
  // first[k] (list_gap_at): the 2 x substeps passes of a step read them in order, where the rows'
  // own gaps lie apart, between the coloured rows (at 30k disks and more, each on its own
  // cache line from memory).
  std::vector<PairGap> list_gap;
  std::size_t list_gap_at(int p, std::size_t k) const {
    std::size_t at = first[k];
    for (int e = 0; e < p; ++e) at += static_cast<std::size_t>(n[e][k]);
    return at;
  }
  // Scratch of the colouring: the live rows of each block, at live[first[k] ..], their
  // disks at live_disks[first[k] ..] and whether each found a colour at in_lane[first[k] ..].
  struct Pair {
    int a, b;
  };
  std::vector<int> live, live_count;
  std::vector<Pair> live_disks;
  std::vector<std::uint8_t> in_lane;
  // The liner rows of the disk stages' range r (Workers::kDiskGrain disks from r times
  // that): [liner_at[r], liner_at[r + 1]).
  std::vector<std::size_t> liner_at;
  // Scratch of the restitution: the bouncing rows of pair block k at bounce[first[k] ..]
  // and of liner range r at liner_bounce[liner_at[r] ..], bounce_n[k] and
  // bounce_n[blocks + r] of them.
  std::vector<int> bounce, liner_bounce, bounce_n;
  std::size_t live_n = 0;         // pair rows carrying an impulse into the step (timing)
};

// Plan the step's rows: the blocks and their phase lists, the colouring of the live rows
// (built here: the warm start applies them) in lanes, the liner ranges. block_disks comes
// from the broad phase.
void colour_live_rows(const Model& model, const Disks& disks, const StepStart& start,
                      int block_disks, Contacts& contacts, SolverRows& rows, Workers& workers);
// Gravity's share of the first substep (the relax adds the later substeps').
void integrate_velocities(const Model& model, Disks& disks, Workers& workers);
// Apply the impulses carried into the substep.
void warm_start(const Contacts& contacts, SolverRows& rows, Disks& disks, Workers& workers);
// One soft Gauss-Seidel pass (elapsed_s: the time since the step began, for the liner's
// travel), then symplectic Euler with the new velocities; dp accumulates the displacement
// of the step. A disk's position is integrated in the pass's last stage, in the same range
// as its liner rows (after every row of the pass has touched it): a stage and a sweep over
// the disks fewer than integrating them in a stage of its own, with the same bits.
void solve_and_integrate_positions(const Model& model, const StepStart& start, double elapsed_s,
                                   double mill_speed_rad_s, Contacts& contacts, SolverRows& rows,
                                   Disks& disks, Workers& workers);
// One rigid pass without bias; adds the substep's impulses to the step sums. gravity_after:
// then the next substep's gravity, the same way.
void relax(const Model& model, const StepStart& start, double elapsed_s,
           double mill_speed_rad_s, bool gravity_after, Contacts& contacts, SolverRows& rows,
           Disks& disks, Workers& workers);
// The lanes' impulses, step sums and live bits back to the contact arrays.
void store_lanes(SolverRows& rows, PairSet& pairs, Workers& workers);
// Contacts that closed faster than the threshold and carried load get the impulse that
// sends them apart at e times that speed.
void apply_restitution(const Model& model, Contacts& contacts, SolverRows& rows, Disks& disks,
                       Workers& workers);

// Disks per range of the charge-shape sample, whose partial sums are added in range order.
constexpr std::size_t kDisksPerRange = 1024;

}  // namespace millwear::soft
