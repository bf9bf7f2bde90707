#include "cmc/contact/Interaction.hpp"

#include <numbers>
#include <stdexcept>

namespace cmc {

namespace {
bool positive_finite(double x) { return x > 0.0 && std::isfinite(x); }
}  // namespace

ExponentialAdhesion::ExponentialAdhesion(double work, double range) : w(work), rho(range) {
  if (!positive_finite(work) || !positive_finite(range))
    throw std::invalid_argument("ExponentialAdhesion: need a positive, finite work of adhesion w and range rho");
  // The pure exponential: no head, the tail is the whole law (evaluate() then computes
  // exactly −w exp(−g/ρ) and its derivatives, as before the head existed).
  sigma0_ = w / rho;
  tail_a_ = sigma0_;
  tail_w_ = w;
  ell_ = rho;
  inv_ell_ = 1.0 / rho;
  kappa_ = sigma0_ * inv_ell_;
  cut_ = rho * 52.0 * std::numbers::ln2;  // exp(-g/rho) < 2^-52 beyond
}

ExponentialAdhesion ExponentialAdhesion::with_head(double work, double sigma0, double kappa) {
  if (!positive_finite(work) || !positive_finite(sigma0) || !positive_finite(kappa))
    throw std::invalid_argument("ExponentialAdhesion::with_head: need a positive, finite w, sigma0 and kappa");
  const double lo = sigma0 * sigma0 / (2.0 * work), hi = sigma0 * sigma0 / work;
  if (kappa < lo * (1.0 - 1e-12) || kappa > hi * (1.0 + 1e-12))
    throw std::invalid_argument("ExponentialAdhesion::with_head: the head slope kappa must lie between sigma0^2/(2w) "
                                "(the triangle) and sigma0^2/w (the exponential)");
  ExponentialAdhesion a(work, work / sigma0);
  if (kappa >= hi) return a;  // the pure exponential
  a.kappa_ = kappa;
  a.sigma0_ = sigma0;
  // κ g1 = σ0 − sqrt(2 w κ − σ0²) (the work; Interaction.hpp); a = σ0 − κ g1.
  // (Within round-off of the triangle, the triangle: no tail of vanishing length.)
  const double excess = 2.0 * work * kappa - sigma0 * sigma0;
  const double root = excess > 1e-12 * sigma0 * sigma0 ? std::sqrt(excess) : 0.0;
  a.tail_a_ = root;
  a.g1_ = (sigma0 - root) / kappa;
  if (root > 0.0) {
    a.ell_ = root / kappa;
    a.inv_ell_ = 1.0 / a.ell_;
    a.tail_w_ = root * a.ell_;
    a.cut_ = a.g1_ + a.ell_ * 52.0 * std::numbers::ln2;
  } else {  // the triangle: nothing beyond g1
    a.ell_ = a.inv_ell_ = a.tail_w_ = 0.0;
    a.cut_ = a.g1_;
  }
  return a;
}

ExponentialAdhesion shape_coarse_grained(double w, double rho, double k_self) {
  const double kappa = kCoarseGrainingMargin * k_self, sigma0 = w / rho;
  if (w / (rho * rho) <= kappa) return ExponentialAdhesion(w, rho);  // monostable as it is
  if (sigma0 * sigma0 / (2.0 * w) <= kappa) return ExponentialAdhesion::with_head(w, sigma0, kappa);
  return ExponentialAdhesion::with_head(w, std::sqrt(2.0 * w * kappa), kappa);  // the triangle, peak lowered
}

DugdaleAdhesion::DugdaleAdhesion(double work, double range, double smoothing_width)
    : w(work), h0(range), smoothing(smoothing_width) {
  if (!positive_finite(work) || !positive_finite(range))
    throw std::invalid_argument("DugdaleAdhesion: need a positive, finite work of adhesion w and range h0");
  if (!(smoothing_width >= 0.0) || !(smoothing_width < 2.0 * range))
    throw std::invalid_argument("DugdaleAdhesion: need a smoothing width 0 <= eps < 2 h0");
  sigma0_ = w / h0;
  lo_ = h0 - 0.5 * smoothing;
  hi_ = h0 + 0.5 * smoothing;
  inv_eps_ = smoothing > 0.0 ? 1.0 / smoothing : 0.0;
}

double tabor_parameter(double Estar, double R, double w, double rho) {
  if (!positive_finite(Estar) || !positive_finite(R) || !positive_finite(w) || !positive_finite(rho))
    throw std::invalid_argument("tabor_parameter: need Estar, R, w, rho > 0");
  return std::cbrt(R) * std::pow(w / Estar, 2.0 / 3.0) / rho;
}

double exponential_range_from_tabor(double Estar, double R, double w, double mu_T) {
  if (!positive_finite(Estar) || !positive_finite(R) || !positive_finite(w) || !positive_finite(mu_T))
    throw std::invalid_argument("exponential_range_from_tabor: need Estar, R, w, mu_T > 0");
  return std::cbrt(R) * std::pow(w / Estar, 2.0 / 3.0) / mu_T;
}

double dugdale_stress_from_lambda(double Estar, double R, double w, double lambda) {
  if (!positive_finite(Estar) || !positive_finite(R) || !positive_finite(w) || !positive_finite(lambda))
    throw std::invalid_argument("dugdale_stress_from_lambda: need Estar, R, w, lambda > 0");
  const double K = 4.0 * Estar / 3.0;
  return 0.5 * lambda * std::cbrt(std::numbers::pi * w * K * K / R);
}

DugdaleAdhesion dugdale_from_lambda(double Estar, double R, double w, double lambda, double smoothing) {
  const double sigma0 = dugdale_stress_from_lambda(Estar, R, w, lambda);
  return DugdaleAdhesion(w, w / sigma0, smoothing);
}

double dugdale_min_smoothing(double Estar, double sigma0, double dx) {
  if (!positive_finite(Estar) || !positive_finite(sigma0) || !positive_finite(dx))
    throw std::invalid_argument("dugdale_min_smoothing: need Estar, sigma0, dx > 0");
  return 2.0 * sigma0 * dx / (1.2 * Estar);
}

}  // namespace cmc
