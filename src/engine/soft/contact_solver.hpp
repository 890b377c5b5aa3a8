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
// solved four at a time in vector lanes (colour_solve.hpp); the serial pass keeps the rest,
// with its skip of inert rows and lazy building. In each pass the serial rows go first,
// then the colours in order, then the liner contacts (last, so that they win: the liner
// must not be pushed through). Gauss-Seidel order is therefore not key order; it is still
// fixed by the contact list, so results are bit-identical run to run, and the same with
// four (AVX2) or two (SSE2) lanes per register.
#include <cstddef>
#include <vector>

#include "engine/soft/colour_solve.hpp"
#include "engine/soft/contact_set.hpp"
#include "engine/soft/disks.hpp"
#include "engine/soft/model.hpp"

namespace millwear::soft {

// Which disk-pair rows are solved how, this step.
struct SolverRows {
  ColouredRows coloured;          // the live rows that found a colour, in lanes
  std::vector<int> serial;        // the others, key order
  std::size_t serial_n = 0;
  // The live rows among the serial ones, key order, for the warm start: set by the
  // colouring for the first substep and by each relax for the next.
  std::vector<int> warm;
  std::size_t warm_n = 0;
  std::size_t live_n = 0;         // pair rows carrying an impulse into the step (timing)
};

// Colour the live rows (building them: the warm start applies them) and fill the lanes.
void colour_live_rows(const Model& model, const Disks& disks, const StepStart& start,
                      PairSet& pairs, SolverRows& rows);
// Gravity's share of the substep.
void integrate_velocities(const Model& model, Disks& disks);
// Apply the impulses carried into the substep.
void warm_start(const Contacts& contacts, SolverRows& rows, Disks& disks);
// One soft Gauss-Seidel pass; elapsed_s is the time since the step began (liner travel).
void solve(const Model& model, const StepStart& start, double elapsed_s,
           double mill_speed_rad_s, Contacts& contacts, SolverRows& rows, Disks& disks);
// Symplectic Euler with the new velocity; dp accumulates the displacement of the step.
void integrate_positions(const Model& model, Disks& disks);
// One rigid pass without bias; adds the substep's impulses to the step sums.
void relax(const Model& model, const StepStart& start, double elapsed_s,
           double mill_speed_rad_s, Contacts& contacts, SolverRows& rows, Disks& disks);
// The lanes' impulses, step sums and live bits back to the contact arrays.
void store_lanes(SolverRows& rows, PairSet& pairs);
// Contacts that closed faster than the threshold and carried load get the impulse that
// sends them apart at e times that speed.
void apply_restitution(const Model& model, Contacts& contacts, Disks& disks);

}  // namespace millwear::soft
