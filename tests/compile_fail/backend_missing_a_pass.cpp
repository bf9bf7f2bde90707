// A backend that lacks one pass, handed to the iteration it is meant for: this translation
// unit must not compile, and the compiler must name the backend concept the iteration
// requires (tests/compile_fail/compile_fail.cmake). With CMC_EVERY_PASS the backend has
// every pass and the unit must compile: the failure is then the missing pass's, not some
// other mistake of this file.
//   CMC_POLONSKY_KEER: pk::iterate over a backend without stiffness_and_sums
//   CMC_QUASI_STATIC:  qs::solve over a backend without predict
#include "cmc/contact/polonsky_keer/Iteration.hpp"
#include "cmc/contact/quasi_static/Iteration.hpp"

#include <cstddef>
#include <cstdint>

namespace {

using namespace cmc;

#if defined(CMC_POLONSKY_KEER)
// The passes and combined operations of a Polonsky-Keer backend (pk::PolonskyKeerBackend),
// doing nothing.
struct Backend : pk::Fields {
  template <class F>
  void all(std::size_t, F) {}
  template <class Acc, class F>
  Acc reduce_in(const std::uint8_t*, std::size_t, F) { return {}; }
  template <class Acc, class F>
  Acc reduce_in_or_below(const std::uint8_t*, const double*, double, std::size_t, F) { return {}; }
  double sum(const double*) { return 0.0; }
  template <class Acc, class F>
  Acc direction_and_curvature(const std::uint8_t*, F, double&) { return {}; }
  template <class Acc, class F>
  Acc exact_and_gap_sums(double, const std::uint8_t*, double, F) { return {}; }
  template <class Acc, class F>
  Acc linear_and_gap_sums(double, double, const std::uint8_t*, double, F) { return {}; }
  template <class Acc, class StepAcc, class P, class C, class F>
  Acc project_and_gap_sums(P, C, bool, const std::uint8_t*, double, F, StepAcc&, pk::StepChoice&) { return {}; }
#if defined(CMC_EVERY_PASS)
  template <class Acc, class Fill, class F>
  Acc stiffness_and_sums(Fill, const std::uint8_t*, F) { return {}; }
#endif
};

[[maybe_unused]] pk::End solve(Backend& b, const PolonskyKeer::Options& o, const Target& target, const pk::Start& start,
                               SolveResult& res) {
  return pk::iterate(b, o, 1.0, target, start, res);
}
#endif

#if defined(CMC_QUASI_STATIC)
// The passes of a quasi-static backend (qs::QuasiStaticBackend), doing nothing.
struct Backend {
  std::size_t n = 0;
  template <class F>
  void all(std::size_t, F) {}
  template <class Acc, class F>
  Acc reduce(std::size_t, F) { return {}; }
  void bind(OuterPoint&) {}
  void start_cold() {}
  void start_warm(Field&&, ContactState&) {}
  void start_from(OuterPoint&) {}
  void shift_heights() {}
  double mean_tension() { return 0.0; }
  void stop_inner_at(double) {}
  SolveResult inner(const Target&, bool, int, int) { return {}; }
#if defined(CMC_EVERY_PASS)
  void predict(const qs::JumpPrediction&, double) {}
#endif
  double* t() { return nullptr; }
  const double* g() const { return nullptr; }
  const double* x() const { return nullptr; }
  double* p() { return nullptr; }
  void outer_point(OuterPoint&) {}
  bool solved() const { return false; }
  void end(ContactState&) {}
};

[[maybe_unused]] SolveResult solve(Backend& b, HalfSpace& hs, const ExponentialAdhesion& adh,
                                   const QuasiStaticAdhesion::Options& o, const Target& target, ContactState& st) {
  return qs::solve(b, hs, adh, o, qs::JumpPrediction(1.0, adh), 0.0, target, st, nullptr);
}
#endif

}  // namespace
