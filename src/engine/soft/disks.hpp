#pragma once
// The charge as the soft solver holds it: disks in the solver's own order (by grid cell,
// for locality, remapped every few steps by the broad phase), the caller's id beside each.
// The substep passes touch one 64-byte Body per disk (body.hpp); the rest is structure of
// arrays. The ChargeState the engine hands out (by id) is written from these at the end of
// every step (finish.cpp).
#include <cstdint>
#include <vector>

#include "engine/charge.hpp"
#include "engine/soft/body.hpp"
#include "engine/soft/workers.hpp"

namespace millwear::soft {

struct Disks {
  int n = 0;
  std::vector<int> id;        // the caller's index of each disk
  std::vector<int> slot;      // by the caller's index: the disk's place in the solver's order
  // n + 1 bodies: body n is the dummy that the padding lanes of the wide solve read and
  // write (zero inverse mass and inertia, never reordered).
  std::vector<Body> body;
  std::vector<double> x, y, angle, radius, mass;
  std::vector<std::uint8_t> active, species;
  std::vector<double> margin;  // this step's speculative margin (broad_phase.cpp)
};

// What the step started from, for what is computed from the start state after the
// substeps began (a row built lazily in the middle of the solve, the accounting of the
// energy the impulses changed, the solver's position correction). A disk's velocities are
// one 32-byte record: a pair's build and its accounting read both disks' at once.
struct alignas(32) StartVelocity {
  double vx = 0, vy = 0, w = 0;  // also the "before" velocities of the energy accounting
};
struct StepStart {
  std::vector<double> y;             // heights (the position correction's potential energy)
  std::vector<StartVelocity> v;
};

// The initial charge, in id order; inactive disks get zero inverse mass and inertia.
Disks load_disks(const ChargeState& charge);
StepStart make_step_start(int n);
// Record what the step starts from and zero the displacements; after any reordering.
void record_step_start(Disks& disks, StepStart& start, Workers& workers);

}  // namespace millwear::soft
