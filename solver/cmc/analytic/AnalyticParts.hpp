// Pieces shared by the analytic references' files (Numerics.cpp, Analytic.cpp,
// SphereAdhesion.cpp): argument checks that throw std::invalid_argument naming the
// function, and GSL's error handler switched off for a scope. Internal to analytic/.
#pragma once

#include <gsl/gsl_errno.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace cmc::analytic::parts {

constexpr double pi = std::numbers::pi;

// ---- argument checks (NaN fails every one of them)
inline void require(bool ok, const char* fn, const char* message) {
  if (!ok) throw std::invalid_argument(std::string("cmc::analytic::") + fn + ": " + message);
}
inline bool positive(double x) { return x > 0 && std::isfinite(x); }
inline bool nonnegative(double x) { return x >= 0 && std::isfinite(x); }

// Switches GSL's abort-on-error handler off for the lifetime of the object.
class GslErrorsOff {
 public:
  GslErrorsOff() : previous_(gsl_set_error_handler_off()) {}
  ~GslErrorsOff() { gsl_set_error_handler(previous_); }
  GslErrorsOff(const GslErrorsOff&) = delete;
  GslErrorsOff& operator=(const GslErrorsOff&) = delete;

 private:
  gsl_error_handler_t* previous_;
};

}  // namespace cmc::analytic::parts
