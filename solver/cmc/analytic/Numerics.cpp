// The GSL numerics of the analytic references (Analytic.hpp, namespace numerics): every
// GSL return code checked, exceptions of the integrand carried across GSL's C frames.
#include "cmc/analytic/Analytic.hpp"
#include "cmc/analytic/AnalyticParts.hpp"

#include <gsl/gsl_integration.h>
#include <gsl/gsl_min.h>
#include <gsl/gsl_roots.h>

#include <exception>
#include <limits>
#include <memory>

namespace cmc::analytic {

using parts::GslErrorsOff;

namespace {

// Lets GSL's C code call a std::function. An exception must not unwind through C frames:
// it is stored, GSL sees NaN (and stops with an error), and the exception is rethrown.
struct Callback {
  const numerics::Function* f;
  std::exception_ptr error{};

  static double call(double x, void* self) noexcept {
    auto* cb = static_cast<Callback*>(self);
    if (cb->error) return std::numeric_limits<double>::quiet_NaN();
    try {
      return (*cb->f)(x);
    } catch (...) {
      cb->error = std::current_exception();
      return std::numeric_limits<double>::quiet_NaN();
    }
  }
  gsl_function gsl() { return gsl_function{&Callback::call, this}; }
  void after(int status, const std::string& what, const char* step) const {
    if (error) std::rethrow_exception(error);
    if (status != GSL_SUCCESS)
      throw std::runtime_error(what + ": GSL " + step + " failed: " + gsl_strerror(status));
  }
};

template <class T, void (*Free)(T*)>
std::unique_ptr<T, void (*)(T*)> owned(T* p, const std::string& what) {
  if (!p) throw std::runtime_error(what + ": GSL allocation failed");
  return {p, Free};
}

}  // namespace

namespace numerics {

double find_root(const Function& f, double lo, double hi, const std::string& what) {
  if (!(lo < hi)) throw std::invalid_argument(what + ": empty root bracket");
  const double flo = f(lo), fhi = f(hi);
  if (!std::isfinite(flo) || !std::isfinite(fhi))
    throw std::runtime_error(what + ": function not finite at the ends of the root bracket");
  if (flo == 0) return lo;
  if (fhi == 0) return hi;
  if ((flo < 0) == (fhi < 0)) throw std::runtime_error(what + ": root not bracketed");

  GslErrorsOff off;
  Callback cb{&f};
  gsl_function F = cb.gsl();
  auto s = owned<gsl_root_fsolver, gsl_root_fsolver_free>(
      gsl_root_fsolver_alloc(gsl_root_fsolver_brent), what);
  cb.after(gsl_root_fsolver_set(s.get(), &F, lo, hi), what, "root bracket");
  const double epsabs = 1e-300;  // relative accuracy decides unless the root is 0
  for (int it = 0; it < 1000; ++it) {
    cb.after(gsl_root_fsolver_iterate(s.get()), what, "root iteration");
    const int status = gsl_root_test_interval(gsl_root_fsolver_x_lower(s.get()),
                                              gsl_root_fsolver_x_upper(s.get()), epsabs, 1e-14);
    if (status == GSL_SUCCESS) return gsl_root_fsolver_root(s.get());
    if (status != GSL_CONTINUE) cb.after(status, what, "root convergence test");
  }
  throw std::runtime_error(what + ": root search did not converge");
}

double minimize(const Function& f, double lo, double guess, double hi, const std::string& what) {
  if (!(lo < guess && guess < hi)) throw std::invalid_argument(what + ": bad minimum bracket");
  const double flo = f(lo), fg = f(guess), fhi = f(hi);
  if (!(fg < flo && fg < fhi)) throw std::runtime_error(what + ": minimum not bracketed");

  GslErrorsOff off;
  Callback cb{&f};
  gsl_function F = cb.gsl();
  auto s = owned<gsl_min_fminimizer, gsl_min_fminimizer_free>(
      gsl_min_fminimizer_alloc(gsl_min_fminimizer_brent), what);
  cb.after(gsl_min_fminimizer_set_with_values(s.get(), &F, guess, fg, lo, flo, hi, fhi), what,
           "minimum bracket");
  // The location of a smooth minimum is only defined to ~sqrt(DBL_EPSILON); the value
  // there is then accurate to ~DBL_EPSILON.
  const double epsabs = 1e-12 * (hi - lo), epsrel = 1e-7;
  for (int it = 0; it < 500; ++it) {
    cb.after(gsl_min_fminimizer_iterate(s.get()), what, "minimiser iteration");
    const int status = gsl_min_test_interval(gsl_min_fminimizer_x_lower(s.get()),
                                             gsl_min_fminimizer_x_upper(s.get()), epsabs, epsrel);
    if (status == GSL_SUCCESS) return gsl_min_fminimizer_x_minimum(s.get());
    if (status != GSL_CONTINUE) cb.after(status, what, "minimiser convergence test");
  }
  throw std::runtime_error(what + ": minimisation did not converge");
}

namespace {
template <class Quadrature>
double quadrature(const Function& f, const std::string& what, Quadrature&& q) {
  constexpr std::size_t limit = 2000;
  GslErrorsOff off;
  Callback cb{&f};
  gsl_function F = cb.gsl();
  auto ws = owned<gsl_integration_workspace, gsl_integration_workspace_free>(
      gsl_integration_workspace_alloc(limit), what);
  double result = 0, abserr = 0;
  cb.after(q(&F, limit, ws.get(), &result, &abserr), what, "integration");
  return result;
}
}  // namespace

double integrate(const Function& f, double lo, double hi, const std::string& what, double epsrel,
                 double epsabs) {
  return quadrature(
      f, what,
      [&](gsl_function* F, std::size_t n, gsl_integration_workspace* w, double* r, double* e) {
        return gsl_integration_qags(F, lo, hi, epsabs, epsrel, n, w, r, e);
      });
}

double integrate_to_infinity(const Function& f, double lo, const std::string& what, double epsrel) {
  return quadrature(
      f, what,
      [&](gsl_function* F, std::size_t n, gsl_integration_workspace* w, double* r, double* e) {
        return gsl_integration_qagiu(F, lo, 0.0, epsrel, n, w, r, e);
      });
}

}  // namespace numerics

}  // namespace cmc::analytic
