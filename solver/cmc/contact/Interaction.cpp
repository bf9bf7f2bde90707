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
  inv_rho_ = 1.0 / rho;
  cut_ = rho * 52.0 * std::numbers::ln2;  // exp(-g/rho) < 2^-52 beyond
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
