#include "cmc/contact/quasi_static/QuasiStaticAdhesion.hpp"

#include "cmc/contact/quasi_static/Iteration.hpp"

#include <cmath>
#include <stdexcept>

namespace cmc {

QuasiStaticAdhesion::QuasiStaticAdhesion(HalfSpace& hs, const Field& heights, ExponentialAdhesion adhesion,
                                         Options o)
    : hs_(hs), h_(heights), adh_(adhesion), opt_(std::move(o)) {
  if (heights.size() != hs.grid().size())
    throw std::invalid_argument("QuasiStaticAdhesion: heights do not match the grid");
  if (!(opt_.tension_tolerance > 0.0)) throw std::invalid_argument("QuasiStaticAdhesion: tension_tolerance must be > 0");
  if (opt_.cascade_slab_rows < 1) throw std::invalid_argument("QuasiStaticAdhesion: cascade_slab_rows must be >= 1");
  // The diagonal of K: the pressure at a point that holds a unit displacement there and
  // zero everywhere else (the same at every point of a translation-invariant grid); and
  // K's entries to the cascade's neighbours. Only these numbers are kept, not the response
  // (a field of the transform grid: 8.6 GB at 32768², which a GPU run cannot spare).
  {
    const Field response = hs.unit_response();
    const int mx = hs.transform_nx(), my = hs.transform_ny();
    k_self_ = hs.transform_entry(response, 0, 0);
    k_near_.resize(std::size_t(qs::kSide * qs::kSide));
    for (int dy = -qs::kRadius; dy <= qs::kRadius; ++dy)
      for (int dx = -qs::kRadius; dx <= qs::kRadius; ++dx)
        k_near_[std::size_t((dy + qs::kRadius) * qs::kSide + dx + qs::kRadius)] =
            hs.transform_entry(response, (dy + my) % my, (dx + mx) % mx);
  }
  if (!(k_self_ > 0.0)) throw std::logic_error("QuasiStaticAdhesion: the half-space's self-stiffness is not positive");
  const double h_scale = PolonskyKeer::residual_scale(heights);
  const bool monostable = adh_.largest_curvature() < k_self_;
  move_floor_ = qs::move_floor(adh_.range(), opt_.tolerance, h_scale, monostable);
  solve_opt_ = opt_;
  solve_opt_.tolerance = qs::inner_tolerance(adh_.range(), opt_.tolerance, h_scale, monostable);
}

#ifndef CMC_CUDA
// A build without the CUDA backend: the case parser refuses backend = "cuda" before a solve.
SolveResult qs::solve_on_device(const Problem&, const Target&, ContactState&, OuterPoint*) {
  throw std::runtime_error("quasi-static adhesion: this build of cmc has no CUDA backend (configure with -DCMC_CUDA=ON)");
}
#endif

SolveResult QuasiStaticAdhesion::solve(const Target& target, ContactState& st, OuterPoint* from) {
  const qs::Problem p{hs_, h_, adh_, solve_opt_, k_self_, k_near_, move_floor_};
  if (solve_opt_.backend == Backend::Cuda && solve_opt_.outer_on_device) return qs::solve_on_device(p, target, st, from);
  return qs::solve_on_cpu(p, target, st, from);
}

}  // namespace cmc
