// The memory the adhesive CG holds, counted from its code (contact/Memory.hpp says what the
// numbers mean and who asks).
#pragma once

#include "cmc/contact/Memory.hpp"

namespace cmc::adhesive {

// On the host. AdhesiveSolver::Work (a member of the solver, kept for the whole run):
// heights, x, Ku, d, Kd, r, c, trial, Ktrial on the transform grid, K h when periodic, the
// bound flags (bytes); the stiffness when periodic. The load path's trial copy of the
// state; with `refine_pulloff`, the pull-off search's best state and its copy; with
// `load_control`, the three points of the bracketing search, each a state. The walk holds
// them while a step is measured and written (its callbacks run inside it).
inline FieldCount host_memory(const MemoryShape& s, bool refine_pulloff, bool load_control) {
  FieldCount f;
  f.run_transform += 9.0 + (s.periodic ? 1.0 : 0.0) + 1.0 / 8.0;
  if (s.periodic) f.run_transform += s.sp() / 2.0 / s.m();
  f.run_grid += 3.0;
  if (refine_pulloff) f.run_grid += 6.0;
  if (load_control) f.run_grid += 9.0;
  f.steps_inside_run = true;
  return f;
}

}  // namespace cmc::adhesive
