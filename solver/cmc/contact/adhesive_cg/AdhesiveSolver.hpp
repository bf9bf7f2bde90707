// Constrained nonlinear conjugate gradients for adhesive (and hard-wall) contact.
//
// Problem: minimise over the surface displacement u the total energy
//     E(u) = U_el(u) + ∫ φ(g) dA,    g = h − δ + u ≥ 0 on the surface,
// with φ one of the interactions of Interaction.hpp (a hard wall at g = 0 is always
// there). φ may be concave (exponential adhesion: φ'' < 0 everywhere), so E is not
// convex and the solver is a careful descent method, not a linear-algebra solve.
//
// Algorithm: projected conjugate gradients in the gap (primal) variables in the form of
// Bugnicourt, Sainsot, Dureisseix, Gauthier & Lubrecht, "FFT-based methods for solving a
// rough adhesive contact: description and convergence study", Tribol. Lett. 66, 29 (2018)
// (their "CG without restart"; NuMPI's ccg_without_restart is the same scheme):
//  * the gradient r = ∂E/∂u = K u + φ'(g) (K = G⁻¹, the elastic stiffness, diagonal in
//    Fourier space), projected on the feasible directions: zero where g = 0 and the point
//    pushes on the wall (r >= μ), minus its mean μ over the free set on a periodic solid
//    (whose mean displacement is fixed; μ = −p̄ is the Lagrange multiplier);
//  * the direction d = −ψ + β d_old with Daniel's β = ψ·Hd_old / d_old·Hd_old
//    (J. W. Daniel, SIAM J. Numer. Anal. 4, 10 (1967); equal to Bugnicourt's Hestenes–
//    Stiefel-like β for a quadratic energy), H = K + diag φ'' at the previous iterate,
//    β clipped at 0, and d projected on the feasible cone (d >= 0 where g = 0);
//  * the step from the exact curvature along d, α = −(ψ·d)/(d·K d + Σ φ''(g) d²);
//  * the projection g ← max(g, 0) and, on a periodic grid, the multiplicative rescale of g
//    that restores the prescribed mean gap (Bugnicourt et al. 2018; it keeps g >= 0 and
//    the contact set).
// Rey, Anciaux & Molinari (Comput. Mech. 60, 69 (2017)) use the same ingredients (a
// projection on g >= 0 plus a mean-gap constraint) in a Polonsky–Keer-like scheme.
//
// Safeguards (what makes it usable on non-convex, multistable problems):
//  * sufficient descent: if ψ·d > −0.01 |ψ|² the direction is reset to −ψ;
//  * negative curvature along d (d·Hd <= 0): a trust step that moves no gap by more than
//    `trust_step` (default: the interaction range ρ or h0), then a reset to −ψ;
//  * energy increase: every step is checked against the exact energy; a step that raises E
//    beyond round-off (1e-11 relative) is backtracked by safeguarded quadratic
//    interpolation (factor 0.1–0.5) up to `max_backtracks` times, then the direction is
//    reset to steepest descent (and the solve stops after 4 such failures in a row);
//  * optional reset whenever a point enters or leaves the wall set (Polonsky & Keer's
//    rule; off by default: Bugnicourt et al. report faster convergence without it on
//    adhesive problems, and our Johnson-sinusoid runs agree);
//  * a cap on iterations, and a check of every reduction for non-finite values: the solver
//    stops cleanly with converged = false and a message, and the returned state is the last
//    finite iterate (g >= 0 exactly). It never throws for a failed solve.
//
// Cost: one FFT pair per iteration (K d; d·Kd comes from Parseval inside the multiply).
// The gaps, K u and the energy are then updated incrementally (g += α d, K u += α K d,
// U += α u·Kd + α²/2 d·Kd), which is exact unless the projection clipped a point (then K u
// is recomputed: one more pair). The periodic mean-gap rescale g ← s g is exact without a
// transform, K u ← s K u + (s − 1) K h, with K h computed once. K u is also recomputed every
// `recompute_every` iterations and before convergence is declared. Measured: 1.1–1.3 pairs
// per iteration over a load step (bench/bench_adhesion.cpp).
//
// Half-spaces:
//  * PeriodicHalfSpace: K = E*|q|/2 on the grid's own FFT (Johnson 1985 §13.2), mean(u) = 0.
//    Displacement control fixes δ, i.e. the mean gap ḡ = mean(h) − δ; the mean pressure is
//    the Lagrange multiplier of that constraint, p̄ = −mean over the free set of (K u + φ').
//  * FreeHalfSpace: the operator's padded circulant of Love/Boussinesq influence
//    coefficients on the grid zero-padded to (2nx) x (2ny) (Hockney 1970; Pastewka & Robbins,
//    Appl. Phys. Lett. 108, 221601 (2016)). The unknowns are the displacements on the whole
//    padded grid, with the interaction and the wall acting on the physical patch only, and
//    K = C⁻¹ (C the padded circulant, inverted exactly in Fourier space). Minimising over
//    the padding displacements as free unknowns gives the Schur complement of C⁻¹, which is
//    exactly (P C Pᵀ)⁻¹, the inverse of the free-boundary operator on the patch (derived;
//    the padding carries zero pressure at convergence, which the residual checks). Each
//    FFT is on the padded grid (4x the points). The interaction is truncated at the patch
//    edge: make the patch contain every point within reach of the interaction.
//
// Residual (what `tolerance` applies to, default 1e-8): the largest violation of the
// equilibrium (KKT) conditions, in pressure units, divided by the pressure scale P:
//     max( |K u + φ'(g) − μ| over points with g > 0 (and |K u| over the padding),
//          max(0, μ − K u − φ'(g)) over points with g = 0 ) / P,
// μ = −p̄ for a periodic solid, 0 for a free one: the largest force imbalance of a free
// point, and the largest tension a contact point would need beyond what the interaction
// provides. P = max(peak tension of the interaction, E* × rms slope of the indenter)
// (pressure_scale()).
//
// Load control (Control::MeanPressure) is an outer search on δ, each evaluation a warm-
// started displacement-controlled solve: secant steps until the target is bracketed, then
// Illinois (modified regula falsi). It lands on the branch the warm start is on, and
// reports not converged when no δ on that branch carries the target (beyond pull-off, or
// a jump in between). Its tolerance on the mean pressure is 10 × tolerance × P.
//
// The parts (contact/adhesive_cg/; each a small named function, constants named and
// explained where they are used):
//  * the CPU backend: the solve's fields (Work) and its per-point passes (evaluation,
//    direction, trial point): CpuBackend.hpp; there is no CUDA backend;
//  * the iteration, written once for every interaction law: Iteration.hpp, with the
//    convergence measure (the KKT residual above, Iteration::digest), the search direction
//    (Daniel's β with the sufficient-descent reset, Iteration::conjugate_beta) and the step
//    rule (exact curvature step, trust step, energy-checked backtracking by safeguarded
//    quadratic interpolation, Iteration::line_search);
//  * load control (the outer secant/Illinois search on δ): LoadControl.hpp;
//  * path control (step halving, jump detection, pull-off): contact/LoadPath.hpp.
// The elastic response is the HalfSpace's (its stiffness K on the transform grid).
#pragma once

#include "cmc/contact/Interaction.hpp"
#include "cmc/contact/Solver.hpp"
#include "cmc/elastic/HalfSpace.hpp"

#include <memory>

namespace cmc {

class AdhesiveSolver {
 public:
  struct Options : SolverOptions {
    Options() { tolerance = 1e-8; }
    // Exact K u every this many incremental steps: bounds the round-off drift of the
    // incremental update K u += α K d, at one FFT pair each (about 3 % of the pairs at 32).
    // The same default as Polonsky–Keer and as the case files' [solver] recompute_every.
    int recompute_every = 32;
    bool restart_on_active_set_change = false;
    double trust_step = 0.0;     // largest gap change of a negative-curvature step; 0: interaction range
    int max_backtracks = 30;     // per line search
    int max_load_iterations = 60;  // outer iterations of load control
  };

  AdhesiveSolver(HalfSpace& half_space, const Field& heights, Interaction interaction, Options options = {});
  ~AdhesiveSolver();
  AdhesiveSolver(const AdhesiveSolver&) = delete;
  AdhesiveSolver& operator=(const AdhesiveSolver&) = delete;

  // Solve for `target`, warm-starting from `state` when it holds a solution on this grid.
  // Displacement control (Control::Penetration) is the primary mode. What the solve did on
  // the way (restarts, backtracks, ...) is in the result's diagnostics.
  SolveResult solve(const Target& target, ContactState& state);

  double pressure_scale() const { return pscale_; }
  const Interaction& interaction() const { return interaction_; }
  const Options& options() const { return opt_; }
  Options& options() { return opt_; }

  struct Work;  // the transform-grid fields of a solve (CpuBackend.hpp)

 private:
  SolveResult solve_displacement(double delta, ContactState& st);

  HalfSpace& hs_;
  const Field& h_;
  Interaction interaction_;
  Options opt_;
  double pscale_ = 1.0;
  std::unique_ptr<Work> w_;
};

}  // namespace cmc
