// The outer iteration of the quasi-static solver (QuasiStaticAdhesion.hpp), written once for
// every backend (what a backend provides: the concept QuasiStaticBackend, Contract.hpp,
// which qs::solve requires): the CPU's (CpuBackend.cpp) and the GPU's (CudaBackend.cuh).
// The backend holds the fields and runs the passes; the steps, the residual, the warm start
// and the end are here.
#pragma once

#include "cmc/contact/quasi_static/Contract.hpp"
#include "cmc/grid/Grid.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace cmc::qs {

// The next tension of point i: the peak tension in contact, else the tension at its
// predicted gap.
struct NextTension {
  const double *g, *x;
  JumpPrediction jump;
  CMC_HD double operator()(std::size_t i) const { return g[i] <= 0.0 ? jump.w_rho : jump.tension(x[i]); }
};

// The inner (Polonsky-Keer) solves of an outer iteration, on either backend: their options,
// made once from the quasi-static solver's, and where their progress lines count from.
class InnerSolves {
 public:
  InnerSolves(const QuasiStaticAdhesion::Options& o, Backend backend) : opt_(o) {
    if (o.progress) {
      po_.progress = [this](const ProgressPoint& p) {
        opt_.progress({before_ + p.iteration, p.residual, outer_ + 1, true});
      };
      po_.progress_every = o.progress_every;
    }
    po_.tolerance = o.tolerance;
    po_.max_iterations = o.max_iterations;
    po_.recompute_every = o.recompute_every;
    po_.precondition = o.precondition;
    po_.backend = backend;
    po_.keep_work = true;  // one solve an outer step: the same arrays each time
    // Each outer solve starts from the exact u of its pressure (Polonsky-Keer's first step),
    // so only the last one needs Polonsky-Keer's confirmation on an exact u: the others skip
    // it, and the converged tension is confirmed by one more solve at the same t (a "confirm"
    // step, usually 0 iterations: one FFT pair and a half instead of one per outer step).
    po_.confirm = false;
  }
  InnerSolves(const InnerSolves&) = delete;  // its progress hook points to it
  InnerSolves& operator=(const InnerSolves&) = delete;
  const PolonskyKeer::Options& options() const { return po_; }
  PolonskyKeer::Options& options() { return po_; }
  // The next solve is outer step `outer`'s, after `iterations_before` inner iterations.
  void at(int outer, int iterations_before) { outer_ = outer, before_ = iterations_before; }

 private:
  const QuasiStaticAdhesion::Options& opt_;
  PolonskyKeer::Options po_;
  int outer_ = 0, before_ = 0;
};

// One solve for a target on the loading branch, over backend b: where it stands between
// outer steps and the parts of an outer step (solve() below runs them). Every member is
// public: nvcc's device lambdas may not sit in private member functions.
template <QuasiStaticBackend B>
struct Outer {
  enum class After { Stop, Confirm, Next };  // what follows a measured outer step

  Outer(B& backend, HalfSpace& half_space, const ExponentialAdhesion& adhesion,
        const QuasiStaticAdhesion::Options& options, const JumpPrediction& jump_prediction, const Target& t)
      : clock(half_space), b(backend), hs(half_space), adh(adhesion), opt(options), jump(jump_prediction), target(t),
        n(backend.n) {}

  // The result, with the counts of the process before a continued solve.
  SolveResult finish(bool converged, std::string msg) {
    clock.finish(res, converged, std::move(msg));
    res.fft_pairs += pairs_before, res.wall_s += seconds_before, res.fft_s += fft_s_before;
    return res;
  }
  // Where the first solve starts: an interrupted solve's outer step, the previous (smaller)
  // load's state, or nothing (the hard-wall solve).
  void start(ContactState& st, OuterPoint* from) {
    b.bind(at);
    warm = !from && st.gap.size() == n && st.pressure.size() == n;
    if (from) {
      continue_from(*from, st);
    } else if (warm) {
      // Its tension, and its repulsive pressure p + t as Polonsky-Keer's warm start (made
      // here, on the host, where the state is).
      Field t(n);
      const double* g = st.gap.data();
      Grid::parallel_for(n, [&](std::size_t i0, std::size_t e) {
        for (std::size_t i = i0; i < e; ++i) t[i] = jump.tension(g[i]);
      });
      double* sp = st.pressure.data();
      Grid::parallel_for(n, [&](std::size_t i0, std::size_t e) {
        for (std::size_t i = i0; i < e; ++i) sp[i] = std::max(0.0, sp[i] + t[i]);
      });
      b.start_warm(std::move(t), st);
    } else {
      b.start_cold();
    }
  }
  void continue_from(OuterPoint& from, ContactState& st) {
    if (from.tension.size() != n || from.inner.pressure.size() != n || from.outer < 1)
      throw std::invalid_argument("QuasiStaticAdhesion: the solve to continue does not fit this grid");
    outer = from.outer;
    res.iterations = from.so_far.iterations;
    res.diagnostics = from.so_far.diagnostics;
    pairs_before = from.so_far.fft_pairs, seconds_before = from.so_far.wall_s, fft_s_before = from.so_far.fft_s;
    // The state is not read: its fields would only sit beside the solve's.
    st.pressure = Field(), st.displacement = Field(), st.gap = Field();
    b.start_from(from);
  }
  // The outer step's Polonsky-Keer solve at the current tension. False: the iteration ends
  // (the solve failed, or reached solver.max_seconds inside).
  bool inner_solve() {
    if (!confirming && (outer > 0 || warm)) b.shift_heights();
    Target tk = target;
    if (target.control == Control::MeanPressure) tk.value = target.value + b.mean_tension();
    const SolveResult r = b.inner(tk, confirming, outer, res.iterations);
    res.iterations += r.iterations;
    res.diagnostics += r.diagnostics;
    if (r.converged) return true;
    if (r.message.rfind(kInnerTimeLimitMessage, 0) == 0) {  // solver.max_seconds inside the solve
      out_of_time = inner_stopped = true;
      pk_message = r.message;
      return false;
    }
    pk_ok = false;
    pk_message = "outer step " + std::to_string(outer) + ": " + r.message;
    return false;
  }
  // The next tension (with jump prediction and cascade), how much it changes, and what follows.
  After measure(double floor) {
    b.predict(jump, floor);
    const NextTension next{b.g(), b.x(), jump};
    const double* tp = b.t();
    // The residual is the largest change either way. Falls come from the inner solves'
    // error as the outer iteration sees it (the jump prediction near a fold amplifies it),
    // and also, with exact inner solves, from the jump prediction during jumps and, under
    // penetration control, from gaps that open far from contact (the top of
    // QuasiStaticAdhesion.hpp, "Measured").
    const RiseFall rf = b.template reduce<RiseFall>(n, [=] CMC_HD(std::size_t i, RiseFall& a) {
      const double d = next(i) - tp[i];
      a.rise = a.rise < d ? d : a.rise;  // std::max(a.rise, d)
      a.fall = a.fall < -d ? -d : a.fall;
    });
    residual = (rf.rise < rf.fall ? rf.fall : rf.rise) / adh.peak_tension();
    worst_fall = std::max(worst_fall, rf.fall / adh.peak_tension());
    if (opt.progress) opt.progress({res.iterations, residual, outer + 1});
    if (!std::isfinite(residual)) {
      pk_ok = false;
      pk_message = "the adhesive tension became non-finite at outer step " + std::to_string(outer);
      return After::Stop;
    }
    if (residual <= opt.tension_tolerance) {
      if (confirming) return After::Stop;
      confirming = true;  // not counted against max_outer
      return After::Confirm;
    }
    if (outer + 1 >= opt.max_outer) return After::Stop;
    if (opt.max_seconds > 0.0 && clock.seconds() >= opt.max_seconds) {
      out_of_time = true;
      return After::Stop;
    }
    confirming = false;
    return After::Next;
  }
  // Warm start of the next solve: keep the total pressure p − t of the points in contact,
  // i.e. raise their repulsion by the change of their tension. The first solve after the
  // hard-wall one then starts from the hard-wall state itself instead of a rescaled
  // pressure (measured at 512²: 119 -> 51 iterations for that solve). The same holds for
  // the points the jump prediction brings into contact (predicted gap 0): they start with
  // the repulsion t_next − t, which keeps their total pressure −t, instead of 0 (a point
  // that joins from overlap takes a projected step, and Polonsky-Keer finds its pressure
  // over many). Only the start changes: each solve is the same convex problem. Measured on
  // the challenge at 250 kPa (2048², dx = 24 ρ): 222 -> 164 iterations, 517 -> 378 FFT
  // pairs, the same 10 outer steps, a_r within one point of 4.2 million (the answer at
  // tolerance 1e-7), mean gap within 3e-8 relative; s = 32 on 1024² (dx = 1.6 ρ): 879 ->
  // 769 iterations, 2032 -> 1714 pairs, the same a_r. Then the tension moves on.
  void next_start() {
    const NextTension next{b.g(), b.x(), jump};
    double* tp = b.t();
    double* pr = b.p();
    const double* x = b.x();
    b.all(n, [=] CMC_HD(std::size_t i) {
      const double tn = next(i);
      if (pr[i] > 0.0 || x[i] <= 0.0) {
        const double q = pr[i] + tn - tp[i];
        pr[i] = q > 0.0 ? q : 0.0;  // std::max(0.0, q)
      }
      tp[i] = tn;
    });
  }
  // Where the solve stands after an unfinished outer step, for Options::on_outer.
  void show_outer() {
    b.outer_point(at);
    at.outer = outer + 1;
    at.so_far.iterations = res.iterations;
    at.so_far.diagnostics = res.diagnostics;
    at.so_far.fft_pairs = pairs_before + clock.pairs();
    at.so_far.wall_s = seconds_before + clock.seconds();
    at.so_far.fft_s = fft_s_before + clock.fft_seconds();
    opt.on_outer(at);
  }
  // The solved state: total pressure p − t, displacement G (p − t), the gap of the solve,
  // and the energy, elastic and adhesive.
  void solved_state(ContactState& st) {
    b.end(st);
    st.mean_pressure = Grid::mean(st.pressure);
    const double* g = st.gap.data();
    const double adhesion = Grid::parallel_reduce<SumReduction>(n, [&](std::size_t i0, std::size_t e, SumReduction& acc) {
                              double s = 0.0;
                              for (std::size_t i = i0; i < e; ++i) s += adh.evaluate(g[i]).energy;
                              acc.v += s;
                            }).v;
    res.energy = hs.energy(st.pressure, st.displacement) + adhesion * hs.grid().cell_area();
  }
  // The result once the iteration ended: converged, or why not.
  SolveResult outcome() {
    if (!pk_ok) return finish(false, pk_message);
    if (out_of_time) return finish(false, time_limit_message());
    if (!(residual > opt.tension_tolerance)) return finish(true, "");
    std::ostringstream s;
    s << kOuterLimitMessage << outer + 1 << " outer steps at tension change " << residual
      << " > tension_tolerance " << opt.tension_tolerance;
    // Falls as large as the tolerance: where measured, the inner solves' error kept the
    // residual up (the challenge at μ_T = 0.706 on 2048², falls up to 3.6e-3 at
    // solver.tolerance 1e-6 and 202 outer steps; 53 at 1e-8; μ_T = 1 on 4096², 1000 steps
    // without converging, 74 at 1e-8). A hint, not a diagnosis: jumps and penetration
    // control make falls with exact inner solves too (QuasiStaticAdhesion.hpp, "Measured").
    if (worst_fall >= opt.tension_tolerance)
      s << "; tensions also fell between outer steps, by up to " << worst_fall
        << " of the peak: where that was measured late in a solve, the inner tolerance " << opt.tolerance
        << " (from solver.tolerance) limited the outer iteration, and a smaller one (e.g. " << opt.tolerance * 1e-2
        << ") converged in fewer outer steps (docs/theory/loading-branch.md, \"Creep\")";
    return finish(false, s.str());
  }
  std::string time_limit_message() const {
    std::ostringstream s;
    s << kTimeLimitMessage << "(solver.max_seconds = " << opt.max_seconds << ") ";
    if (inner_stopped)
      s << "inside outer step " << outer + 1 << "'s Polonsky-Keer solve, after " << clock.seconds() << " s ("
        << pk_message << "): its state is that solve's last iterate, not an equilibrium of the outer step (not "
        << "converged; a larger limit, or none, goes further)";
    else
      s << "after " << outer + 1 << " outer steps and " << clock.seconds() << " s, at tension change " << residual
        << " > tension_tolerance " << opt.tension_tolerance << ": its state is where the outer iteration stood (not "
        << "converged; a larger limit, or none, goes further)";
    return s.str();
  }

  const SolveClock<HalfSpace> clock;
  B& b;
  HalfSpace& hs;
  const ExponentialAdhesion& adh;
  const QuasiStaticAdhesion::Options& opt;
  const JumpPrediction& jump;
  const Target& target;
  const std::size_t n;
  SolveResult res;
  double pairs_before = 0.0, seconds_before = 0.0, fft_s_before = 0.0;  // a continued solve's
  OuterPoint at;             // where the solve stands between outer steps (what on_outer is shown)
  int outer = 0;             // the outer step
  bool warm = false;         // started from the previous load's state
  double residual = 1.0;     // the tension change of the last outer step, over w/ρ
  bool pk_ok = true;         // no inner solve failed
  std::string pk_message;    // why one did, or where the time limit stopped one
  bool confirming = false;   // this solve repeats the last one (same t) on the exact u
  double worst_fall = 0.0;   // the largest fall of a tension between outer steps, over w/ρ
  bool out_of_time = false;  // stopped at opt.max_seconds
  bool inner_stopped = false;  // ... inside an outer step's Polonsky-Keer solve
};

// One solve for `target` on the loading branch (QuasiStaticAdhesion::solve). `hs` counts
// the transforms and holds the elastic energy; `move_floor`: the cascade's (move_floor(),
// Parts.hpp), a length.
template <QuasiStaticBackend B>
SolveResult solve(B& b, HalfSpace& hs, const ExponentialAdhesion& adh, const QuasiStaticAdhesion::Options& opt,
                  const JumpPrediction& jump, double move_floor, const Target& target, ContactState& st,
                  OuterPoint* from) {
  Outer<B> o(b, hs, adh, opt, jump, target);
  if (opt.max_seconds > 0.0 && opt.limit_inner) b.stop_inner_at(steady_seconds() + opt.max_seconds);
  if (target.control == Control::MeanPressure && !(target.value > 0.0))
    return o.finish(false, "quasi-static loading from out of contact reaches no contact at a mean pressure <= 0 "
                           "(the surfaces stay apart); tensile loads are on an unloading path: use [solver] kind = "
                           "\"adhesive_cg\"");
  o.start(st, from);
  const double floor = opt.cascade ? move_floor : HUGE_VAL;
  for (;; ++o.outer) {
    if (!o.inner_solve()) break;
    const typename Outer<B>::After next = o.measure(floor);
    if (next == Outer<B>::After::Stop) break;
    if (next == Outer<B>::After::Confirm) continue;
    o.next_start();
    if (opt.on_outer) o.show_outer();
  }
  o.res.diagnostics.outer_iterations += o.outer + 1;
  o.res.residual = o.residual;
  if (b.solved()) o.solved_state(st);
  return o.outcome();
}

// What a solve on either backend is handed (QuasiStaticAdhesion::solve): the problem and
// the solver's numbers (K's diagonal and its entries to the cascade's 3 x 3 neighbours,
// the cascade's move floor).
struct Problem {
  HalfSpace& hs;
  const Field& heights;
  const ExponentialAdhesion& adhesion;
  const QuasiStaticAdhesion::Options& options;
  double self_stiffness;
  const std::vector<double>& k_near;
  double move_floor;
};
// The solve with the outer step on the CPU (CpuBackend.cpp), and on the GPU
// (CudaBackend.cu; a build without CUDA throws).
SolveResult solve_on_cpu(const Problem& p, const Target& target, ContactState& st, OuterPoint* from);
SolveResult solve_on_device(const Problem& p, const Target& target, ContactState& st, OuterPoint* from);

}  // namespace cmc::qs
