// What a solver's memory count is made of, in plain numbers: each solver counts the memory
// it holds beside its code (polonsky_keer/Memory.hpp, quasi_static/Memory.hpp,
// adhesive_cg/Memory.hpp), and the input layer asks each for its count when it checks a
// case against the machine (input/Memory.cpp, estimate_memory). These headers are the one
// part of contact/ that input/ may include: they include nothing of cmc but each other
// (tests/test_layout.cpp holds them to that).
#pragma once

#include <cmath>

namespace cmc {

// A case's grid as a count sees it.
struct MemoryShape {
  double nx = 0.0, ny = 0.0;
  bool periodic = true;
  int ranks = 1;      // MPI ranks splitting the grid (each holds its slab of every field)
  bool cuda = false;  // grid.backend = "cuda"
  // The transform grid: the grid itself when periodic, 2nx x 2ny zero-padded when free.
  double mx() const { return periodic ? nx : 2.0 * nx; }
  double my() const { return periodic ? ny : 2.0 * ny; }
  double m() const { return mx() * my(); }
  // Doubles of an r2c spectrum of the transform grid ((mx/2 + 1) my complex numbers).
  double sp() const { return 2.0 * (std::floor(mx() / 2.0) + 1.0) * my(); }
};

// The fields a solver holds on the host, by phase, in units of a field of the grid (n
// doubles) and of a field of the transform grid (m doubles). A solve's own fields are freed
// when it returns; those a solver makes in its constructor and frees there are a phase of
// their own, before any state or solve field exists.
struct FieldCount {
  double run_grid = 0.0, run_transform = 0.0;      // for the whole run
  double solve_grid = 0.0, solve_transform = 0.0;  // while a solve runs
  double setup_transform = 0.0;                    // in the solver's constructor only
  // The solver measures and writes a solved step while its run's fields are held (the
  // adhesive CG's load path, whose callbacks run inside it).
  bool steps_inside_run = false;
};

}  // namespace cmc
