#include "cmc/contact/adhesive_cg/AdhesiveSolver.hpp"

#include "cmc/contact/adhesive_cg/Iteration.hpp"
#include "cmc/contact/adhesive_cg/LoadControl.hpp"
#include "cmc/grid/Ranks.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace cmc {

namespace {

// Root mean square slope of the indenter from forward differences (across the periodic
// boundary when periodic; only inside the patch otherwise).
double rms_slope(const Grid& g, const Field& h, bool periodic) {
  struct Acc {
    double s2 = 0.0;
    long cnt = 0;
    void merge(const Acc& o) { s2 += o.s2, cnt += o.cnt; }
  };
  // The row after the slab's last (periodic; from the next rank in a distributed run).
  const Field above = g.ny > 1 ? row_above(g, h) : Field();
  const int rows = g.rows();
  const Acc a = Grid::parallel_reduce<Acc>(std::size_t(rows), [&](std::size_t r0, std::size_t r1, Acc& acc) {
    for (int iy = int(r0); iy < int(r1); ++iy)
      for (int ix = 0; ix < g.nx; ++ix) {
        const std::size_t k = std::size_t(iy) * g.nx + ix;
        double sx = 0.0, sy = 0.0;
        bool ok = true;
        if (periodic || ix + 1 < g.nx) sx = (h[std::size_t(iy) * g.nx + (ix + 1) % g.nx] - h[k]) / g.dx();
        else ok = false;
        if (g.ny > 1) {
          const double up = iy + 1 < rows ? h[std::size_t(iy + 1) * g.nx + ix] : above[ix];
          if (periodic || g.y0 + iy + 1 < g.ny) sy = (up - h[k]) / g.dy();
          else ok = false;
        }
        if (ok) acc.s2 += sx * sx + sy * sy, ++acc.cnt;
      }
  });
  return a.cnt ? std::sqrt(a.s2 / a.cnt) : 0.0;
}

}  // namespace

// ---------------------------------------------------------------- construction

AdhesiveSolver::AdhesiveSolver(HalfSpace& hs, const Field& heights, Interaction interaction, Options o)
    : hs_(hs), h_(heights), interaction_(std::move(interaction)), opt_(std::move(o)), w_(std::make_unique<Work>()) {
  const Grid& g = hs.grid();
  if (heights.size() != g.size()) throw std::invalid_argument("AdhesiveSolver: heights do not match the grid");
  for (double x : heights)
    if (!std::isfinite(x)) throw std::invalid_argument("AdhesiveSolver: heights must be finite");
  Work& w = *w_;
  w.periodic = hs.periodic();
  w.n = g.size();
  w.N = double(g.points());
  w.M = hs.transform_size();
  // Rows of the transform grid held here: a slab of the periodic grid, or of the padded
  // grid of a free boundary (the whole of it in a serial run), of which the first
  // `patch_rows` are rows of the patch (global rows below ny).
  const Grid& ts = hs.transform_slab();
  const int mx = hs.transform_nx(), my = w.periodic ? g.rows() : ts.rows();
  const int patch_rows = w.periodic ? g.rows() : std::clamp(g.ny - ts.y0, 0, ts.rows());
  if (!w.periodic && (g.split() || ts.split())) w.exchange = std::make_unique<RowExchange>(g, ts, g.ny);
  w.shape = adhesive::Shape{g.nx, patch_rows, mx, my, nullptr, nullptr, 0.0};
  w.to_padded(heights, w.hf);
  w.hmean = Grid::mean(heights);
  for (Field* f : {&w.x, &w.Ku, &w.d, &w.Kd, &w.r, &w.c, &w.trial, &w.Ktrial}) f->assign(w.M, 0.0);
  w.bound.assign(w.M, 0);
  if (w.periodic) {
    w.Kh.assign(w.M, 0.0);
    hs.apply(w.hf.data(), w.Kh.data(), hs.stiffness());
  } else {
    hs.stiffness();  // made now, so that a bad operator fails here
  }
  w.shape.h = w.hf.data();  // the shape's dimensions were set above
  w.shape.Kh = w.periodic ? w.Kh.data() : nullptr;
  // Pressure scale: max(peak tension, E* x rms slope of the indenter).
  pscale_ = std::max(peak_tension(interaction_), hs.contact_modulus() * rms_slope(g, heights, w.periodic));
  if (!(pscale_ > 0.0) || !std::isfinite(pscale_)) pscale_ = hs.contact_modulus();
}

AdhesiveSolver::~AdhesiveSolver() = default;

// ---------------------------------------------------------------- one displacement-controlled solve


// ---------------------------------------------------------------- full contact

namespace {

// Full contact on a periodic solid: at δ = mean(h) the mean gap is zero, so g = 0
// everywhere, u = δ − h and K u = −K h, and the mean pressure p̄ is free: the pressure
// p = −K h + p̄ is admissible wherever it is at least the interaction's force at contact,
// p ≥ f(0) (Interaction.hpp), i.e. for every p̄ ≥ f(0) + max K h. Its displacement-
// controlled solve reports the smallest such p̄, so a load-control search that walks to
// δ = mean(h) below its target ends there without a bracket. For a target at or above
// that bound this is the exact answer (a flat indenter: uniform pressure p̄, gap 0):
// written into `st` with its energy, and true. `st` is the search's last state.
bool full_contact_state(const AdhesiveSolver::Work& w, const Field& h, const Interaction& inter, double target,
                        double cell_area, ContactState& st, double& energy, double& residual) {
  if (!w.periodic || st.gap.size() != w.n || st.penetration < w.hmean) return false;
  if (Grid::max(st.gap) > 0.0) return false;  // the search did not end in full contact
  const InteractionValue at_contact = evaluate(inter, 0.0);
  const double pbar_min = at_contact.force + Grid::max(w.Kh);
  if (!(target >= pbar_min)) return false;  // below it the surfaces part: not full contact
  const std::size_t n = w.n;
  st.pressure.resize(n), st.displacement.resize(n), st.gap.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    st.displacement[i] = w.hmean - h[i];
    st.pressure[i] = target - w.Kh[i];
  }
  const double u_Ku = -Grid::dot(st.displacement, w.Kh);  // Σ u K u, for the elastic energy
  st.penetration = w.hmean;
  st.mean_pressure = Grid::mean(st.pressure);
  energy = (0.5 * u_Ku + w.N * at_contact.energy) * cell_area;
  residual = 0.0;  // g = 0 and p >= f(0) everywhere: every KKT condition holds exactly
  return true;
}

}  // namespace

// ---------------------------------------------------------------- entry points

SolveResult AdhesiveSolver::solve(const Target& target, ContactState& st) {
  if (!std::isfinite(target.value)) {
    SolveResult r;
    r.message = "AdhesiveSolver: the target is not a finite number";
    return r;
  }
  if (target.control == Control::Penetration) return solve_displacement(target.value, st);
  // Load control: an outer search on δ. Its tolerance on the mean pressure is 10x the
  // residual tolerance in pressure units, so that the inner solves' residual does not
  // decide whether the target is met.
  const double range = interaction_range(interaction_);
  const double hmin = Grid::min(h_), hmax = Grid::max(h_);
  const double span = std::max(hmax - hmin, range);
  const bool warm = st.gap.size() == hs_.grid().size();
  adhesive::LoadControlOptions lc;
  lc.tolerance = 10.0 * opt_.tolerance * pscale_;
  lc.max_iterations = opt_.max_load_iterations;
  // First step: 1 % of the height span from a cold start, 0.1 % from a warm one (the
  // previous load step is close), and never below the interaction range.
  lc.first_step = std::max({(warm ? 1e-3 : 1e-2) * span, range, 1e-12});
  lc.start = warm ? st.penetration : hmin;
  if (w_->periodic) {
    lc.max_penetration = w_->hmean;
    lc.start = std::min(lc.start, w_->hmean);
  }
  SolveResult res = adhesive::solve_for_mean_pressure(
      [this](double d, ContactState& s) { return solve_displacement(d, s); }, target.value, st, lc);
  if (!res.converged && full_contact_state(*w_, h_, interaction_, target.value, hs_.grid().cell_area(), st,
                                           res.energy, res.residual)) {
    res.converged = true;
    res.message.clear();
  }
  return res;
}

SolveResult AdhesiveSolver::solve_displacement(double delta, ContactState& st) {
  const SolveClock clock(hs_);
  SolveResult res;
  auto finish = [&](bool converged, std::string msg) { return clock.finish(res, converged, std::move(msg)); };
  if (w_->periodic && w_->hmean - delta < 0.0) {
    std::ostringstream s;
    s << "AdhesiveSolver: penetration " << delta << " exceeds the mean height " << w_->hmean
      << ": a periodic solid (mean(u) = 0) has no admissible state with mean gap " << w_->hmean - delta << " < 0";
    return finish(false, s.str());
  }
  // A negative-curvature step moves no gap by more than the trust step: by default the
  // interaction's range, over which φ'' changes by a factor e (exponential law).
  const double range = interaction_range(interaction_);
  const double trust = opt_.trust_step > 0.0 ? opt_.trust_step : range > 0.0 ? range : 1.0;
  return std::visit(
      [&](const auto& inter) {
        adhesive::Iteration<std::decay_t<decltype(inter)>> it(*w_, hs_, inter, opt_, pscale_, trust, delta, res.diagnostics);
        if (!it.start(st)) return finish(false, "AdhesiveSolver: non-finite values in the initial state");
        it.run(res);
        const bool finite = it.write_state(st, res.energy);
        res.residual = it.residual();
        std::string stop_msg = it.stop_message();
        if (!finite && stop_msg.empty()) stop_msg = "non-finite values in the final state";
        const bool ok = stop_msg.empty() && res.residual <= opt_.tolerance && finite;
        if (ok) return finish(true, "");
        std::ostringstream s;
        s << "AdhesiveSolver stopped after " << res.iterations << " iterations at residual " << res.residual
          << (res.residual <= opt_.tolerance ? " <= " : " > ") << "tolerance " << opt_.tolerance;
        if (!stop_msg.empty()) s << ": " << stop_msg;
        return finish(false, s.str());
      },
      interaction_);
}

}  // namespace cmc
