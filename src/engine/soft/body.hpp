#pragma once
// Solver state of one disk of the soft backend: everything a contact row reads or writes
// during the substeps, in one 64-byte cache line (a pair row touches two lines, not
// sixteen scattered arrays). The wide solver (colour_solve) loads a body as two halves of
// four doubles each, so the field order is part of its layout: keep vx, vy, w, dpx first.
// The radius fills the second half: the wide solve and the accounting compute a pair row's
// anchors (and the wide solve its masses) from the bodies they load anyway instead of
// streaming them with every row.
namespace millwear::soft {

struct alignas(64) Body {
  double vx = 0, vy = 0, w = 0;   // velocity
  double dpx = 0, dpy = 0;        // displacement since the step began
  double im = 0, ii = 0;          // inverse mass and inertia (0: inactive)
  double radius = 0;              // a pair row's anchor: r_a = -(radius + s0 / 2) n
};

}  // namespace millwear::soft
