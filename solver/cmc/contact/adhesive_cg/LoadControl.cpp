#include "cmc/contact/adhesive_cg/LoadControl.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

namespace cmc::adhesive {

namespace {

// Bracketing: secant steps may not grow by more than this factor per step (nor shrink
// below 1/10 of the previous step), and overshoot the secant root by 5 % so that the
// target is crossed rather than approached from one side.
constexpr double kMaxGrowth = 4.0, kMinShrink = 0.1, kOvershoot = 1.05;
// Steps in a row that move away from the target before the branch is declared not to
// reach it (past the pull-off, or out of reach of the interaction, where p̄ stops changing).
constexpr int kMaxAway = 3;
// Illinois stops when the bracket is this narrow relative to max(1, |δ|): round-off.
constexpr double kBracketRoundoff = 1e-15;

struct Point {
  double delta = 0.0, f = 0.0;  // f = mean pressure − target
  ContactState state;
};

class Search {
 public:
  Search(const DisplacementSolve& solve, double target, const LoadControlOptions& o)
      : solve_(solve), target_(target), opt_(o), t0_(std::chrono::steady_clock::now()) {}

  // Solve at δ from `warm`; false if the inner solve failed (last_ says why).
  bool evaluate(double delta, const ContactState& warm, Point& out) {
    out.delta = delta;
    out.state = warm;
    last_ = solve_(delta, out.state);
    pairs_ += last_.fft_pairs;
    fft_s_ += last_.fft_s;
    iters_ += last_.iterations;
    diag_ += last_.diagnostics;
    ++diag_.outer_iterations;
    out.f = out.state.mean_pressure - target_;
    return last_.converged;
  }
  bool on_target(const Point& p) const { return std::abs(p.f) <= opt_.tolerance; }
  SolveResult finish(bool ok, std::string msg) const {
    SolveResult res = last_;
    res.converged = ok;
    res.message = std::move(msg);
    res.fft_pairs = pairs_;
    res.fft_s = fft_s_;
    res.iterations = iters_;
    res.diagnostics = diag_;
    res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
    return res;
  }
  SolveResult failed() const { return finish(false, "load control: inner solve failed: " + last_.message); }
  enum class Outcome { Bracketed, OnTarget, Failed, Unreachable };
  Outcome bracket(Point& a, Point& b);
  SolveResult illinois(Point& a, Point& b, ContactState& state);
  double target() const { return target_; }

 private:
  const DisplacementSolve& solve_;
  double target_;
  const LoadControlOptions& opt_;
  std::chrono::steady_clock::time_point t0_;
  SolveResult last_;
  double pairs_ = 0.0, fft_s_ = 0.0;
  int iters_ = 0;
  SolveDiagnostics diag_;
};

// Walk δ from a (solved) in the direction that changes p̄ towards the target until the
// target is crossed: then [a, b] brackets it. b holds the last evaluation.
Search::Outcome Search::bracket(Point& a, Point& b) {
  const double dir = a.f < 0.0 ? 1.0 : -1.0;
  double step = opt_.first_step, slope = 0.0;
  bool have_slope = false;
  int away = 0;
  b = a;
  for (int k = 0; k < opt_.max_iterations; ++k) {
    double next = step;
    if (have_slope && slope > 0.0) next = std::clamp(std::abs(a.f / slope) * kOvershoot, kMinShrink * step, kMaxGrowth * step);
    const double delta = std::min(a.delta + dir * next, opt_.max_penetration);
    if (!evaluate(delta, a.state, b)) return Outcome::Failed;
    if (on_target(b)) return Outcome::OnTarget;
    if ((a.f < 0.0) != (b.f < 0.0)) return Outcome::Bracketed;
    if (b.delta >= opt_.max_penetration) return Outcome::Unreachable;
    away = std::abs(b.f) >= std::abs(a.f) ? away + 1 : 0;
    if (away >= kMaxAway) return Outcome::Unreachable;
    slope = (b.f - a.f) / (b.delta - a.delta);
    have_slope = true;
    step = std::abs(b.delta - a.delta) * (slope > 0.0 ? 1.0 : 2.0);
    a = b;
  }
  return Outcome::Unreachable;
}

// Illinois on the bracket [a, b], each evaluation warm-started from the nearer end.
SolveResult Search::illinois(Point& a, Point& b, ContactState& state) {
  int side = 0;
  Point x;
  for (int k = 0; k < opt_.max_iterations; ++k) {
    double d = b.delta - b.f * (b.delta - a.delta) / (b.f - a.f);
    if (!(d > std::min(a.delta, b.delta) && d < std::max(a.delta, b.delta))) d = 0.5 * (a.delta + b.delta);
    if (!evaluate(d, std::abs(d - a.delta) < std::abs(d - b.delta) ? a.state : b.state, x)) {
      state = std::move(x.state);
      return failed();
    }
    if (on_target(x) || std::abs(b.delta - a.delta) <= kBracketRoundoff * std::max(1.0, std::abs(d))) {
      state = std::move(x.state);
      if (std::abs(x.f) <= opt_.tolerance) return finish(true, "");
      std::ostringstream s;
      s << "load control: the mean pressure jumps across penetration " << d << " (" << a.f + target_ << " to "
        << b.f + target_ << "): no stable state carries " << target_;
      return finish(false, s.str());
    }
    if ((x.f < 0.0) == (b.f < 0.0)) {
      b = std::move(x);
      if (side == -1) a.f *= 0.5;
      side = -1;
    } else {
      a = std::move(x);
      if (side == 1) b.f *= 0.5;
      side = 1;
    }
  }
  state = std::abs(a.f) < std::abs(b.f) ? a.state : b.state;
  std::ostringstream s;
  s << "load control: no convergence in " << opt_.max_iterations << " outer iterations";
  return finish(false, s.str());
}

}  // namespace

SolveResult solve_for_mean_pressure(const DisplacementSolve& solve, double target, ContactState& state,
                                    const LoadControlOptions& o) {
  Search search(solve, target, o);
  Point a, b;
  // A failed inner solve hands on where it stopped (a state on the grid, flagged not
  // converged by the result), never an empty or stale state.
  if (!search.evaluate(o.start, state, a)) {
    state = std::move(a.state);
    return search.failed();
  }
  if (search.on_target(a)) {
    state = std::move(a.state);
    return search.finish(true, "");
  }
  switch (search.bracket(a, b)) {
    case Search::Outcome::Failed:
      state = std::move(b.state);
      return search.failed();
    case Search::Outcome::OnTarget:
      state = std::move(b.state);
      return search.finish(true, "");
    case Search::Outcome::Unreachable: {
      std::ostringstream s;
      s << "load control: no penetration found that carries mean pressure " << target
        << " on this branch (beyond pull-off, or full contact); last mean pressure " << b.f + target;
      state = std::move(b.state);
      return search.finish(false, s.str());
    }
    case Search::Outcome::Bracketed:
      break;
  }
  return search.illinois(a, b, state);
}

}  // namespace cmc::adhesive
