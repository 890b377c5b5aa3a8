#pragma once
// Coloured, lane-wide solve of the soft backend's load-carrying disk-pair contacts, after
// the method of Box2D v3 (graph colouring, contacts solved several at a time in SIMD
// lanes), written for disks. No Box2D code is used.
//
// Why. The pair contacts are in key order, so consecutive rows share their first disk and
// the serial Gauss-Seidel pass is one long dependency chain through that disk's velocity:
// each row waits for the one before. Contacts of one colour share no disk, so kLanes of
// them are solved at once (one vector operation per formula), and the chunks of a colour
// do not wait for each other either.
//
// What is coloured is the engine's choice (contact_solver.cpp colours the rows that carry an
// impulse into the step); everything else stays in its serial pass. A contact that finds
// no free colour among kMaxColours stays serial too. The disk-liner contacts are not
// coloured: the liner is one body of infinite mass, so they conflict only through their
// disk, but they are few (about 7% of the acting rows at 3k disks) and stay in the serial
// pass after the colours, which gives them the last word against the wall.
//
// Determinism. The colouring is greedy in the order the contacts are added (the first
// colour free at both disks), so it depends on the contact list only. A lane computes what
// the serial row computes, operation for operation (no contraction: -ffp-contract=off), so
// the results do not depend on the vector width: four doubles per register where the CPU
// has AVX2, two (SSE2, the x86-64 baseline) otherwise, chosen at run time.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "engine/soft/body.hpp"

namespace millwear::soft {

constexpr int kLanes = 4;

// kLanes contacts' rows, structure of arrays: what a row needs that its bodies do not give.
// The names are those of contact_set.hpp's PairGap, PairRow, Impulse and StepSum: unit
// normal from b toward a, start separation, friction coefficient, rolling lever, the
// substep's impulses: 288 bytes a chunk. The anchors (alpha = r_a + s0 / 2, beta = r_b +
// s0 / 2) and the effective masses are computed in the lanes, with the serial row's
// operations, from the radius, inverse mass and inertia of the bodies each pass loads
// anyway: the same bits as storing them, in 72 bytes a row instead of 112 (at 30k disks and
// more the passes stream the rows from memory; docs/benchmarks.md). The step's impulse sums
// are a chunk array of their own (WideSums), written by the relax only.
struct alignas(32) WideRows {
  int a[kLanes], b[kLanes];
  double nx[kLanes], ny[kLanes], s0[kLanes];
  double mu[kLanes], lever[kLanes];
  double ln[kLanes], lt[kLanes], lr[kLanes];
};
static_assert(sizeof(WideRows) == 288, "a chunk's rows are 288 bytes");
struct alignas(32) WideSums {
  double pn[kLanes], pt[kLanes], pr[kLanes];
};

// The solve pass's constants (the relax uses inv_h only).
struct WideSoftness {
  double inv_h = 0, bias_rate = 0, mass_scale = 1, impulse_scale = 0, push = 0;
};

// The passes over all chunks in order (colour after colour): the same rows as the engine's
// serial warm start, soft solve and relax. The relax also adds the impulses to the sums.
void wide_warm_start(Body* body, WideRows* rows, std::size_t chunks);
void wide_solve(Body* body, WideRows* rows, std::size_t chunks, const WideSoftness& soft);
void wide_relax(Body* body, WideRows* rows, WideSums* sums, std::size_t chunks, double inv_h);

// The lane width in use: 4 (AVX2) or 2 (the SSE2 baseline). The pair search's scan follows
// it (narrow_phase.cpp: four candidates at a time where the lanes are four wide). Forcing
// the baseline on a CPU with AVX2 is how a test checks that both widths give the same bits
// (set it before any engine steps; it is a process-wide switch, not meant to change mid-run).
int lane_width();
void force_baseline_lanes(bool on);

// The colouring and the chunks. Per step: begin, add the contacts, layout, fill the lanes
// (the coloured contacts' slots; the other slots are padding lanes, already filled with an
// inert row between two dummy bodies), solve, read the lanes back. Arrays keep their
// high-water size: no allocation per step once warm.
class ColouredRows {
 public:
  static constexpr int kMaxColours = 24;

  // Starts a step over bodies 0 .. bodies - 1, with room for up to `contacts` adds. Body
  // index `bodies` is the dummy that padding lanes read and write (the caller's body array
  // must have it, with zero inverse masses).
  void begin(int bodies, std::size_t contacts);
  // Gives contact q between bodies a and b the first colour free at both; false when none is.
  bool add(int q, int a, int b) {
    const std::uint32_t free = ~(mask_[a] | mask_[b]) & kAllColours;
    if (free == 0) return false;
    const int c = __builtin_ctz(free);
    mask_[a] |= 1u << c;
    mask_[b] |= 1u << c;
    added_[added_n_++] = {q, c, 0};
    count_[c] += 1;
    return true;
  }
  // Colour after colour, each padded to whole chunks.
  void layout();

  // The coloured contacts in the order added, with their slots (after layout): filling and
  // reading the lanes in this order sweeps the contact arrays once, where slot order sweeps
  // them once per colour.
  std::size_t coloured() const { return added_n_; }
  int coloured_contact(std::size_t t) const { return added_[t].q; }
  std::size_t coloured_slot(std::size_t t) const { return added_[t].slot; }
  int colours() const { return colours_; }
  // Chunks [colour_begin(c), colour_begin(c + 1)) hold colour c: they share no body, so
  // they may be solved in any order, or at once, with the same bits.
  std::size_t colour_begin(int c) const { return first_[c]; }
  WideRows* rows() { return wide_.data(); }
  const WideRows* rows() const { return wide_.data(); }
  WideSums* sums() { return sums_.data(); }
  WideRows& chunk_of(std::size_t slot) { return wide_[slot / kLanes]; }
  WideSums& sums_of(std::size_t slot) { return sums_[slot / kLanes]; }

 private:
  static constexpr std::uint32_t kAllColours = (1u << kMaxColours) - 1;
  struct Added {
    int q, colour;
    std::size_t slot;
  };
  int dummy_ = 0;
  std::vector<std::uint32_t> mask_;  // per body: the colours it already has
  std::vector<Added> added_;
  std::size_t added_n_ = 0;
  int count_[kMaxColours] = {};
  std::size_t chunks_ = 0;
  int colours_ = 0;
  std::size_t first_[kMaxColours + 1] = {};
  std::vector<WideRows> wide_;
  std::vector<WideSums> sums_;
};

}  // namespace millwear::soft
