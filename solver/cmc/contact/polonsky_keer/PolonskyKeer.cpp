#include "cmc/contact/polonsky_keer/PolonskyKeer.hpp"

#include "cmc/contact/polonsky_keer/CpuBackend.hpp"  // PolonskyKeer::Work

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace cmc {

#ifndef CMC_CUDA
// A build without the CUDA backend: the case parser refuses backend = "cuda" before a solve.
void PolonskyKeer::DeviceDelete::operator()(Device*) const noexcept {}
pk::End pk::solve_on_device(std::unique_ptr<PolonskyKeer::Device, PolonskyKeer::DeviceDelete>&, HalfSpace&,
                            const Field&, const PolonskyKeer::Options&, double, const Target&, ContactState&,
                            const Start&, SolveResult&) {
  throw std::runtime_error("Polonsky-Keer: this build of cmc has no CUDA backend (configure with -DCMC_CUDA=ON)");
}
#endif

PolonskyKeer::PolonskyKeer(HalfSpace& hs, const Field& heights, Options o)
    : hs_(hs), h_(heights), opt_(std::move(o)), h_scale_(residual_scale(heights)) {
  if (heights.size() != hs.grid().size()) throw std::invalid_argument("PolonskyKeer: heights do not match the grid");
}

double PolonskyKeer::residual_scale(const Field& heights) {
  const double hm = Grid::mean(heights);
  const double var = Grid::parallel_reduce<SumReduction>(heights.size(), [&](std::size_t b, std::size_t e, SumReduction& acc) {
                       double s = 0.0;
                       for (std::size_t i = b; i < e; ++i) s += (heights[i] - hm) * (heights[i] - hm);
                       acc.v += s;
                     }).v;
  const double scale = std::sqrt(var / double(Grid::total(heights.size())));
  return scale > 0.0 ? scale : 1.0;
}

PolonskyKeer::~PolonskyKeer() = default;

SolveResult PolonskyKeer::solve(const Target& target, ContactState& st) {
  const SolveClock clock(hs_);
  SolveResult res;
  auto finish = [&](bool converged, std::string msg) { return clock.finish(res, converged, std::move(msg)); };
  if (target.control == Control::MeanPressure && !(target.value >= 0.0))
    return finish(false, "Polonsky-Keer needs a non-negative mean pressure (no adhesion in a hard-wall solve)");

  const std::size_t n = h_.size();
  const double warm_sum = st.pressure.size() == n ? Grid::sum(st.pressure) : 0.0;
  pk::Start start = pk::make_start(hs_, target, warm_sum > 0.0, st.penetration, opt_.precondition);
  pk::End end;
  if (opt_.backend == Backend::Cuda) {
    end = pk::solve_on_device(device_, hs_, h_, opt_, h_scale_, target, st, start, res);
  } else {
    if (start.warm) start.warm_sum = warm_sum;  // what the CPU backend's b.sum(p) would give
    end = pk::solve_on_cpu(work_, hs_, h_, opt_, h_scale_, target, st, start, res);
  }
  // ---- the solved state. The reported gap is the solution's: zero where pressure is
  // carried, and the non-negative gap elsewhere; how far the iterate is from that is the
  // residual. w = h + u becomes the displacement again.
  // One pass, which also sums p and p u (the mean pressure and the elastic energy): a
  // solve's last reads of p and u.
  Field &p = st.pressure, &u = st.displacement;
  // At zero load no point carries pressure and w = h: the indenter rests on its lowest point
  // (the rigid-body position a vanishing load tends to), wherever the heights' zero lies.
  if (target.control == Control::MeanPressure && target.value == 0.0 && end.failure.empty()) end.delta = Grid::min(u);
  const double sigma = end.sigma, delta = end.delta;
  st.gap.resize(n);
  struct Sums {
    double p = 0.0, pu = 0.0;
    void merge(const Sums& o) { p += o.p, pu += o.pu; }
  };
  const Sums sums = Grid::parallel_reduce<Sums>(n, [&](std::size_t b, std::size_t e, Sums& acc) {
    Sums local;
    for (std::size_t i = b; i < e; ++i) {
      if (sigma != 1.0) p[i] *= sigma;
      st.gap[i] = p[i] > 0.0 ? 0.0 : std::max(0.0, u[i] - delta);
      u[i] -= h_[i];
      local.p += p[i], local.pu += p[i] * u[i];
    }
    acc.merge(local);
  });
  st.penetration = delta;
  st.mean_pressure = sums.p / double(Grid::total(n));
  res.energy = hs_.energy_from_sum(sums.pu);
  std::string msg;
  const bool ok = pk::converged(end, res, opt_.tolerance, msg);
  return finish(ok, msg);
}

}  // namespace cmc
