// Polonsky–Keer constrained conjugate gradients for non-adhesive (hard-wall)
// contact: I. A. Polonsky and L. M. Keer, "A numerical method for solving rough
// contact problems based on the multi-level multi-summation and conjugate gradient
// techniques", Wear 231, 206–219 (1999), §3 (steps (a)–(h)); here with FFT
// convolutions instead of multi-level summation, under mean-pressure (force) or
// penetration (displacement) control.
//
// Cost: the Green's function is applied to the search direction once per iteration
// (one FFT pair). The solver keeps the transform t̂ of the direction, so the displacement
// of the new pressure p' = s (p − τ t) is one inverse transform, w = h + s ((w − h) − τ G t),
// exact (up to round-off) whenever the step changed no point's contact status; when it did
// (points clipped to zero pressure or points added from overlap), or every
// `recompute_every` iterations, or before declaring convergence, w = h + G p is made
// afresh from p (one forward transform more). It iterates on w = h + u.
//
// Residual (what `tolerance` applies to): the rms gap over points carrying pressure
// together with the rms overlap (negative gap) elsewhere, divided by the rms height
// fluctuation of the indenter (or 1 for a flat one): a dimensionless measure of how
// far the complementarity conditions g ≥ 0, p ≥ 0, p g = 0 are from holding.
#pragma once

#include "cmc/contact/Solver.hpp"
#include "cmc/elastic/HalfSpace.hpp"
#include "cmc/grid/Backend.hpp"

#include <memory>

namespace cmc {

// How the message of a Polonsky-Keer solve stopped at Options::stop_at begins.
inline constexpr const char* kInnerTimeLimitMessage = "Polonsky-Keer reached its time limit ";

class PolonskyKeer {
 public:
  struct Options : SolverOptions {
    // Exact displacement every this many linear steps: bounds the drift of the
    // incremental update of the linear steps (round-off), at one forward transform each.
    int recompute_every = 32;
    // Precondition the conjugate gradients on the contact set with the half-space's
    // stiffness K = G⁻¹ (periodic boundary only): the direction is built from z = P K P g
    // (P: restriction to the contact set, g the gap there) instead of g, as in Vollebregt,
    // J. Comput. Phys. 257, 333 (2014), whose FFT-based preconditioner approximates the
    // inverse of the contact-set block of G by the inverse of the whole operator. Exact at
    // full contact; costs one more FFT pair per iteration.
    bool precondition = true;
    // Before declaring convergence, recompute u from the real-space p and test again
    // (removes the drift of the linear steps' incremental update; one FFT pair). A caller that
    // solves again from the returned state before using it (an outer iteration) may turn
    // this off and confirm only its last solve: the next solve starts from the exact u.
    bool confirm = true;
    // Keep the work arrays (the direction, the preconditioned gap, G t, the contact set, the
    // fused sweeps' transform; on the GPU every device field) from one solve to the next
    // instead of making them anew: for a caller that solves many times in a row (the
    // quasi-static solver's outer steps), it saves touching fresh pages in every solve.
    // Off: they live within a solve only (what the memory estimate of a hard-wall run counts).
    bool keep_work = false;
    // Stop, not converged, at the end of the first iteration after this moment of the steady
    // clock (steady_seconds(), Solver.hpp); 0: never. The quasi-static solver's time limit
    // (solver.max_seconds) sets it, so that one long inner solve cannot carry a run past its
    // limit (message kInnerTimeLimitMessage...).
    double stop_at = 0.0;
    // Where the iteration runs (grid/Backend.hpp). Cuda: the fields live on the GPU for
    // the whole solve (CudaBackend.cu; periodic boundary, one process); the
    // heights and a warm start go up at its start, p and u come down at its end, and the
    // solved state is made from them on the host as on the CPU.
    Backend backend = Backend::Cpu;
    // CPU, periodic grid held by one process: run the iteration's passes inside the
    // transforms' sweeps (grid/RowColumnFourier.hpp), where rows and blocks are in cache.
    // Off: the passes and the 2-D transforms one after the other (what a free boundary or a
    // distributed grid does always). Both give the same iterates up to round-off.
    bool fused_sweeps = true;
  };

  PolonskyKeer(HalfSpace& half_space, const Field& heights, Options options);
  ~PolonskyKeer();
  PolonskyKeer(const PolonskyKeer&) = delete;
  PolonskyKeer& operator=(const PolonskyKeer&) = delete;
  // Solve for `target`, starting from `state` when it holds a pressure field.
  SolveResult solve(const Target& target, ContactState& state);
  void set_confirm(bool on) { opt_.confirm = on; }
  void set_stop_at(double t) { opt_.stop_at = t; }
  // The scale of the residual: the rms height fluctuation of `heights` (1 for a flat one).
  static double residual_scale(const Field& heights);
  struct Work;    // a solve's work arrays on the CPU (CpuBackend.hpp)
  struct Device;  // the same on the GPU (CudaBackend.cuh)
  struct DeviceDelete {
    void operator()(Device* d) const noexcept;
  };

 private:
  HalfSpace& hs_;
  const Field& h_;
  Options opt_;
  double h_scale_;
  std::unique_ptr<Work> work_;
  std::unique_ptr<Device, DeviceDelete> device_;
};

}  // namespace cmc
