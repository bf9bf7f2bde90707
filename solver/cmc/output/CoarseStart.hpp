// Starting a run from a coarser run of the same case (a coarse-to-fine warm start: solve on
// n/2, interpolate, finish on n): `cmc run CASE --set grid.n=N --start-from DIR`,
// DIR a finished run of the same case on N/m points (m a whole number) with its fields
// (output.fields = true).
//
// What it is for: the scaled challenge family's resolved members (Δx ≤ 0.8 ρ) take hours
// on one machine; a cold quasi-static solve starts from the hard-wall contact and moves the
// contact fronts to the adhesive ones one outer step at a time. From the coarser grid's
// answer, interpolated, they start near where they end.
//
// Why the gaps are raised. The quasi-static solver reaches the loading-branch state (the
// largest equilibrium) when it starts from above it: from tensions nowhere larger than
// the answer's, i.e. gaps nowhere smaller (QuasiStaticAdhesion.hpp). An interpolated coarse
// answer is close to the fine one but not above it everywhere: where the coarse grid
// closed a gap that the fine one keeps open, the solve can end in a neighbouring
// equilibrium with a few more points in contact. Raising every gap of the start by `lift`
// lowers every start tension by the factor exp(−lift/ρ) (exponential law); the caller
// passes the interaction's range ρ (a factor e), chosen before measuring and kept because it
// holds, not derived: the coarse and fine answers differ by less than ρ in gap except where
// a contact front moves. Measured on one thread ("cold": the same case from the hard-wall
// start):
//  * s = 16 at 4096² (dx = 0.77 ρ) from 2048² (1.55 ρ; a 147 s run), raised by ρ: 149
//    outer steps, 1211 iterations, 3313 FFT pairs, 1435 s beside another run, against the
//    stored cold run's 1882 iterations, 4930 pairs, 2228 s; a_r 9 points of 16.8 million
//    lower (1.1e-5 relative; the cold run was made on another machine, whose FFT plans
//    differ), repulsive a_r 3 points, mean gap 8e-7 relative: 500 times below that
//    member's refinement error.
//  * s = 32 at 2048² (0.80 ρ) from 1024² (1.59 ρ; 43 s), cold: 180 outer steps, 4881 pairs,
//    496 s. Not raised: 120 outer steps, 2519 pairs, 239 s, and a_r 8 points of 4.2
//    million higher (0.0535684 against 0.0535665): a neighbouring equilibrium, not the
//    loading-branch state. Raised by ρ (a prototype that wrote the start into a checkpoint;
//    its warm-start pressure differs slightly from this code's): 141 outer steps, 3076
//    pairs, a_r identical to the last bit, mean gap 3e-7 relative.
//  * Where the finer grid is itself bistable the raise is not enough. The challenge (s = 1)
//    with the shape coarse-graining at 4096² (dx = 11.8 ρ) from 2048² (23.6 ρ; a 189 s run),
//    raised by the law's range (6.4 nm): 871 iterations, 2399 pairs, 1073 s against the cold
//    run's 1022, 2802, 1279 s (whose a_r, 0.0320969, is the stored one to the last bit); a_r
//    150 points of 16.8 million higher (3e-4 relative), repulsive a_r 63 points, mean gap
//    1e-5 relative lower: a neighbouring equilibrium, and no time saved counting the 2048²
//    run. Use it for resolved grids (dx ≲ 1.5 ρ), where it was measured to hold.
//  * s = 128 at 256² from 128² (tests/start_from_test.py, same_state): the same contact
//    and repulsive fractions, 31 outer steps and 488 pairs against 37 and 658. Starting
//    from below instead (every gap lowered by 3 ρ) ends 12 % higher in a_r: the test fails.
// A run started this way says so in its summary.json ("start_from", with the lift), so its
// numbers are never taken for a cold start's.
//
// Scope: one load step, the quasi-static or Polonsky–Keer solver, periodic boundary, one
// process (a distributed run reads its start on every rank: not written yet).
#pragma once

#include "cmc/contact/Solver.hpp"
#include "cmc/input/Case.hpp"
#include "cmc/scene/Scene.hpp"

#include <filesystem>

#include <toml++/toml.h>

namespace cmc {

struct CoarseStart {
  ContactState state;  // on the scene's grid, reduced units
  toml::table record;  // for summary.json: where it came from (folder, grid, factor, load)
};

// The last step of the finished run in `dir` (its result.h5), prolonged onto the scene's
// grid. Every check names the file and what to change (CaseError, exit code 2): a folder
// without a finished run, a run without fields, another box size, a grid that does not
// divide this one, another surface (rms height difference at the shared points above 1 %
// of the rms height; the same case on two grids differs by round-off, measured 4e-9
// relative), a larger load than this case's, a case this start does
// not serve. `lift` (reduced length, >= 0): added to every gap of the start (see above).
CoarseStart read_coarse_start(const std::filesystem::path& dir, const Case& c, const Scene& s, double lift);

// Periodic bilinear prolongation by a whole factor m: fine point (m i, m j) takes coarse
// point (i, j), the points between interpolate linearly in x and y (wrapping at the
// edges). Exact on fields linear in x and y between coarse points.
Field prolong(const Field& coarse, int cnx, int cny, int m);

}  // namespace cmc
