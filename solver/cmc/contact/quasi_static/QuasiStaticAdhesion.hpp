// The loading-branch state of an adhesive contact: the state that quasi-static loading
// from out of contact reaches (approach, jump into contact, then monotone loading to the
// target), computed without following the path.
//
// Why that state is well defined, and which one it is (derived here; the argument is the
// "no-passing" rule of driven elastic manifolds, A. A. Middleton, Phys. Rev. Lett. 68, 670
// (1992), cited from memory):
//  * In the gaps g the energy is E(g) = ½ (g − h)ᵀ K (g − h) + Σ φ(g_i) + P Σ g_i (load
//    control; K the half-space stiffness, P the mean pressure), with g ≥ 0. The off-
//    diagonal elements of K are negative (the real-space kernel of E*|q|/2 is −E*/(4π r³)
//    for r ≠ 0) and φ acts point by point: the system is cooperative (closing one gap
//    closes its neighbours).
//  * For a cooperative system, overdamped relaxation preserves order (if g ≤ g' at one
//    time, then at all later times), so quasi-static loading from out of contact ends in
//    the largest equilibrium (in every gap) among those below the start: the maximal
//    equilibrium at the target load. Sudden loading under overdamped relaxation ends in
//    the same state. Inertia (FIRE, GFMD with little damping) or conjugate-gradient
//    overshoot can end in another, smaller-gap, state: the answer of such a solver
//    depends on its path, which made the adhesive CG's results on the challenge differ
//    between reruns that rounded differently.
//
// Algorithm (majorise-minimise on the concave adhesion, i.e. the concave-convex procedure
// of A. L. Yuille & A. Rangarajan, Neural Comput. 15, 915 (2003), cited from memory):
// exponential adhesion is concave in g (φ'' < 0), so its tangent at the current gaps is
// an upper bound of it. Each outer step replaces φ by that tangent: a fixed tension
// t = φ'(g_k) = (w/ρ) exp(−g_k/ρ) on every point, i.e. a hard-wall problem on the shifted
// heights h − G t at mean pressure P + <t>, solved by Polonsky–Keer (PolonskyKeer.hpp,
// warm-started). The map g_k → g_{k+1} is order-preserving, and starting from a state
// whose gaps are nowhere smaller than the answer's (the hard-wall solution at the same
// load, or the previous step of a loading path) the gaps decrease monotonically to the
// maximal equilibrium: the loading-branch state, not another local minimum.
// Measured: the end state, yes; every outer step, no. With inner solves to
// 1e-10 on the 24 ρ patch of tests/test_quasi_static.cpp, tensions fall between outer
// steps by up to 8.6e-5 of the peak during the jumps under mean-pressure control, and by
// 3e-3 at the first step under penetration control (then 0.57 times less a step), and
// both end in the same state (QuasiStatic.LoadAndPenetrationControlReachOneState). Two
// causes, told apart by the gaps between successive solves: under penetration control
// gaps open, 11239 points (all farther than 5 ρ from contact, by 0.16 ρ on average) at the
// second outer step: on a periodic grid at fixed penetration the displacement's mean is
// fixed, so the tension that lifts the contact lowers the surface elsewhere, and the
// cooperative argument above does not hold. Under mean-pressure control no gap opens (the
// penetration follows the mean tension), so there the falls are the jump prediction's: a
// point is predicted lower than the next solve and the next prediction bear out (the
// cascade counts its neighbours' predicted moves as made). A fall is therefore not by itself the inner
// solves' error (the residual below; docs/theory/loading-branch.md, "Creep").
//
// Jump prediction. Near a bistable point (the grid spacing of the challenge is 24 ρ: every
// point is bistable) the plain iteration creeps: a point about to jump into contact
// needs many outer steps. After each solve, every point with 0 < g < cutoff takes,
// instead of φ'(g), the tension at its own new equilibrium with every other gap held
// (one nonlinear Jacobi step): the largest x ≤ g with k (g − x) = φ'(x) − t (k the
// diagonal of K, one number on a translation-invariant grid), or x = 0 (a jump into
// contact) if there is none. With every other gap held the point's response is the
// stiffest there is, so x is never below the maximal equilibrium's gap and the iteration
// stays monotone. Cascade: a point that moves by Δ pulls its neighbour m by K_mi Δ, which
// may make m jump in turn; this is followed point by point (nonlinear Gauss-Seidel on the
// exact K of the 8 nearest points; the rest, negative, is left out, which pulls less than
// the truth). Moves smaller than the move floor are not passed on (qs::move_floor,
// quasi_static/Parts.hpp: it follows the inner tolerance, and at tight inner tolerances it
// brings in, within one outer step, jumps that a point and its neighbours make together and
// that the iteration otherwise reached by creeping over tens of outer steps). On a 128²
// patch at dx = 24 ρ: 7 outer steps instead of 111, 10.2x fewer
// FFT pairs, the same state (tests/test_quasi_static.cpp). The GPU runs the cascade in
// parallel rounds instead (nonlinear Jacobi over the same stencil, Parts.hpp):
// on the challenge at 512² and 2048² the same outer steps, iterations and contact set as
// the queue, the mean gap within 1.2e-9 and 3.6e-10 relative.
//
// Where the parts are (contact/quasi_static/): the outer iteration is written once
// (Iteration.hpp) over a backend that holds the fields (Contract.hpp): the CPU's
// (CpuBackend.cpp) or, with backend = cuda, the GPU's (CudaBackend.cu: the outer step on
// the device too); the per-point parts of both in Parts.hpp.
//
// Residual: the largest change of the tension, relative to the peak tension w/ρ, that one
// more outer step would make (with jump prediction and cascade), max |t_next − t| / (w/ρ),
// together with each Polonsky–Keer solve reaching `tolerance` (its own residual).
// Converged when both hold. A point that creeps towards an instability more slowly than
// `tension_tolerance` per outer step is not followed: measured on the challenge at 512²,
// tension_tolerance 1e-3 leaves 1 point of 262144 out of contact that 1e-4 and 1e-5 bring
// in (a_r 0.0381279 against 0.0381317; mean gap differs by 4e-7 relative).
//
// Cost: each outer step is one warm-started Polonsky–Keer solve (its warm start keeps the
// total pressure of the points in contact and of those predicted to jump into it) plus
// two and a half FFT pairs (G t, the transform of the shifted heights, the first
// displacement). The challenge at 250 kPa: 10 outer steps at 2048², 164 Polonsky-Keer
// iterations, 68 of them in the first (hard-wall) solve.
//
// Scope: exponential adhesion and the shape coarse-graining's laws (Interaction.hpp; all
// concave, the jump prediction uses their closed forms), any
// boundary, mean-pressure or penetration control, steps of increasing load only (the
// loading branch). Unloading, pull-off and Dugdale adhesion are the adhesive CG's
// (AdhesiveSolver.hpp).
#pragma once

#include "cmc/contact/Interaction.hpp"
#include "cmc/contact/polonsky_keer/PolonskyKeer.hpp"
#include "cmc/contact/Solver.hpp"
#include "cmc/elastic/HalfSpace.hpp"

#include <functional>
#include <vector>

namespace cmc {

// Where a solve stands between two of its outer steps: enough to continue it bit for bit
// in another process (a checkpoint inside a load step, for runs longer than a machine is
// held: the challenge family's resolved members take hours on one machine). Polonsky–Keer's
// next solve needs only its warm-start pressure and the penetration (it recomputes u from
// p, and the gap at its end); the shifted heights are recomputed from the tension.
struct OuterPoint {
  int outer = 0;        // outer steps done (the next one's index)
  // Where the solve's fields live elsewhere (the GPU's outer step): copies tension and
  // inner.pressure and .penetration here; a reader calls it first. Empty: they are here.
  std::function<void()> fetch;
  Field tension;        // t, the fixed tension of the next outer step
  ContactState inner;   // Polonsky–Keer's warm start: pressure and penetration are used
  SolveResult so_far;   // iterations, FFT pairs, wall time and diagnostics of the steps done
};

// How the message of a solve that reached Options::max_outer begins. A run that stops so
// keeps its last checkpoint (Writer.hpp): resumed with a larger limit, it goes on.
inline constexpr const char* kOuterLimitMessage = "quasi-static adhesion stopped after ";
// How the message of a solve that reached Options::max_seconds begins. Its run ends (no
// checkpoint is kept: where it stopped depends on the machine's speed).
inline constexpr const char* kTimeLimitMessage = "quasi-static adhesion reached its time limit ";

class QuasiStaticAdhesion {
 public:
  struct Options : SolverOptions {
    // Tolerance of each Polonsky-Keer solve (its residual, PolonskyKeer.hpp); tighter where
    // a monostable law's move floor is under the solves' error (inner_tolerance()).
    Options() { tolerance = 1e-8; }
    // Outer convergence: the largest tension change of one more outer step, over w/ρ.
    double tension_tolerance = 1e-3;
    int max_outer = 1000;
    // Seconds the solve may take in this process (0: no limit): reached, it stops at the end
    // of an outer step with the state it stands at (message kTimeLimitMessage...), or, where
    // an outer step's Polonsky-Keer solve is still running then (limit_inner), inside it, with
    // that solve's last iterate (the message says so). Why inside: on an H200 a 16384² run
    // with max_seconds = 142 and inner tolerance 1e-8 was still inside an inner solve at
    // about 163 s, and a cap from outside at 180 s killed it with nothing written.
    double max_seconds = 0.0;
    // max_seconds also stops a Polonsky-Keer solve in flight (off: only at the ends of outer
    // steps, which a long inner solve can put far past the limit; tests).
    bool limit_inner = true;
    int recompute_every = 32;  // passed to Polonsky-Keer
    bool precondition = true;  // passed to Polonsky-Keer (its stiffness preconditioner)
    bool predict_jumps = true;  // the nonlinear Jacobi prediction (off: the plain iteration)
    bool cascade = true;        // jumps that trigger jumps within an outer step (needs predict_jumps)
    // Where the solve runs. Cuda: every field of the outer step stays on the GPU with
    // Polonsky-Keer's (CudaBackend.cu; periodic boundary, one process), and
    // the cascade runs in rounds (cascade_rounds); with outer_on_device off, only the
    // Polonsky-Keer solves run there and the outer step on the CPU (the first GPU path,
    // kept to compare with).
    Backend backend = Backend::Cpu;
    bool outer_on_device = true;
    // The cascade in parallel rounds (Parts.hpp), as the GPU runs it, instead of
    // the queues (periodic grid, one process). The same state within the move floor; the
    // CPU's default is the queues (fewer passes on a few cores). On for the GPU's outer step
    // whatever is set here.
    bool cascade_rounds = false;
    // The height of the cascade's slabs in rows (CpuBackend.cpp: a queue per slab,
    // the slabs in parallel, at most 64 of them; a grid of fewer than twice this many rows is
    // one slab, the whole grid's queue). A number of the grid, not of the thread count, so
    // that the answer is the same on any number of threads.
    int cascade_slab_rows = 64;
    // Called after every outer step that leaves the solve unfinished, with where it stands
    // (the solver's own fields, not copies): a caller may save it and hand it back to
    // solve() in another process to continue.
    std::function<void(const OuterPoint&)> on_outer;
  };

  QuasiStaticAdhesion(HalfSpace& half_space, const Field& heights, ExponentialAdhesion adhesion,
                      Options options = {});

  // Solve for `target` on the loading branch. `state`, when it holds a solution on this
  // grid, must come from a smaller (or equal) load of the same loading path: it is the
  // start from above. Otherwise the solve starts from the hard-wall solution. `from`: where
  // an interrupted solve of the same target stood (Options::on_outer); it is moved from,
  // `state` is then not read, and the result is the uninterrupted solve's bit for bit
  // (wall time aside), its counters those of the whole solve.
  SolveResult solve(const Target& target, ContactState& state, OuterPoint* from = nullptr);

  const Options& options() const { return opt_; }
  double self_stiffness() const { return k_self_; }
  // K to the 3 x 3 nearest points, entry (dy + 1) 3 + dx + 1 (the cascade's stencil).
  const std::vector<double>& near_stiffness() const { return k_near_; }
  // The cascade's move floor, a length (qs::move_floor, Parts.hpp).
  double move_floor() const { return move_floor_; }
  // The tolerance the inner solves run at (qs::inner_tolerance, Parts.hpp): options().tolerance
  // unless the move floor of a monostable law is near the inner solves' error.
  double inner_tolerance() const { return solve_opt_.tolerance; }

 private:
  HalfSpace& hs_;
  const Field& h_;
  ExponentialAdhesion adh_;
  Options opt_;
  double k_self_ = 0.0;
  std::vector<double> k_near_;  // K to the 3 x 3 nearest points (the cascade's stencil)
  double move_floor_ = 0.0;
  Options solve_opt_;  // opt_ with the inner solves' tolerance (inner_tolerance())
};

}  // namespace cmc
