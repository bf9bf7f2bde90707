// The device backend of the quasi-static solver's outer iteration (Iteration.hpp; its
// contract: Contract.hpp): see CudaBackend.cu. Included by .cu files (and by the host
// emulation's tests, tests/emulation).
#pragma once

#include "cmc/contact/polonsky_keer/CudaBackend.cuh"
#include "cmc/contact/quasi_static/Iteration.hpp"

#include <string>
#include <vector>

namespace cmc::qs {

struct DeviceSteps {
  DeviceSteps(HalfSpace& hs, const Field& heights, const QuasiStaticAdhesion::Options& o,
              const std::vector<double>& k_near)
      : n(heights.size()), hs_(hs), h_(heights), opt_(o), nx_(hs.grid().nx), ny_(hs.grid().ny),
        stencil_(qs::make_stencil(nx_, ny_, true, k_near)), h_scale_(PolonskyKeer::residual_scale(heights)),
        d_(hs, o.precondition), H0(n, "the heights"), TEN(n, "the tension"), A(n, "the passed-on gaps"),
        inner_(o, Backend::Cuda) {
    H0.upload(heights.data(), n);
    d_.H.upload(heights.data(), n);  // hp = h until a tension shifts it
  }
  const std::size_t n;

  template <class F>
  void all(std::size_t k, F f) {
    cuda::all(k, f);
  }
  template <class Acc, class F>
  Acc reduce(std::size_t k, F f) {
    return d_.reducer.run<Acc>(k, cuda::Everywhere{}, f);
  }

  void bind(OuterPoint&) {}  // outer_point() is handed the OuterPoint it fills
  void start_cold() {
    double* t = TEN.data();
    cuda::all(n, [=] __device__(std::size_t i) { t[i] = 0.0; });
    have_p_ = false;
  }
  void start_warm(Field&& t, ContactState& st) {
    TEN.upload(t.data(), n);
    d_.P.upload(st.pressure.data(), n);
    delta_ = st.penetration;
    have_p_ = true;
    // The state's fields are made anew at the end: the host holds no copy meanwhile.
    st.pressure = Field(), st.displacement = Field(), st.gap = Field();
  }
  void start_from(OuterPoint& from) {
    TEN.upload(from.tension.data(), n);
    d_.P.upload(from.inner.pressure.data(), n);
    delta_ = from.inner.penetration;
    have_p_ = true;
    from.tension = Field(), from.inner = ContactState();
  }
  // hp = h − G t into Polonsky-Keer's heights: t's transform in the scratch spectrum, times
  // the compliance (1/N folded in), and the inverse into the heights' buffer.
  void shift_heights() {
    const Counted c = counted();
    d_.fft.forward(TEN.data(), d_.out);
    double* o = d_.out;
    const double* k = d_.ker;
    cuda::all(d_.nspec, [=] __device__(std::size_t j) { o[2 * j] *= k[j], o[2 * j + 1] *= k[j]; });
    double* hp = d_.H.data();
    d_.fft.inverse(d_.out, hp);
    const double* h0 = H0.data();
    cuda::all(n, [=] __device__(std::size_t i) { hp[i] = h0[i] - hp[i]; });
  }
  double mean_tension() {
    const double* t = TEN.data();
    return d_.reducer.run<Sum>(n, cuda::Everywhere{}, [=] __device__(std::size_t i, Sum& a) { a.v += t[i]; }).v /
           double(n);
  }
  // Polonsky-Keer on the device's heights from its own pressure, as PolonskyKeer::solve
  // does on the host: then p times σ, and the gap (zero where p > 0) into the direction's
  // buffer, which the next solve overwrites.
  void stop_inner_at(double t) { inner_.options().stop_at = t; }
  SolveResult inner(const Target& tk, bool confirm, int outer, int iterations_before) {
    const Counted c = counted();
    inner_.at(outer, iterations_before);
    PolonskyKeer::Options& po = inner_.options();
    po.confirm = confirm;
    const bool warm = have_p_ && d_.sum(d_.p) > 0.0;
    const pk::Start start = pk::make_start(hs_, tk, warm, delta_, opt_.precondition);
    SolveResult res;
    const pk::End end = pk::run_on_device(d_, po, h_scale_, tk, start, res);
    double* p = d_.p;
    double* g = d_.t;
    const double* w = d_.w;
    const double sigma = end.sigma, delta = end.delta;
    cuda::all(n, [=] __device__(std::size_t i) {
      if (sigma != 1.0) p[i] *= sigma;
      const double gi = w[i] - delta;
      g[i] = p[i] > 0.0 ? 0.0 : (gi > 0.0 ? gi : 0.0);
    });
    delta_ = delta;
    have_p_ = true;
    std::string msg;
    res.converged = pk::converged(end, res, po.tolerance, msg);
    res.message = msg;
    return res;
  }
  void predict(const qs::JumpPrediction& jump, double floor) {
    if (!opt_.predict_jumps) {
      x_ = d_.t;  // the gaps themselves
      return;
    }
    // x in G t's buffer, a in its own, the flags in the contact mask's and the scratch
    // spectrum's (each at least n bytes); the gap is in the direction's.
    cuda::ProfileScope ps(cuda::profile().cascade_s);
    cuda::profile().rounds += qs::cascade_rounds(*this, n, d_.t, TEN.data(), jump, stencil_, nx_, ny_, floor, d_.gt,
                                                 A.data(), d_.m, reinterpret_cast<std::uint8_t*>(d_.out));
    ++cuda::profile().cascades;
    x_ = d_.gt;
  }
  double* t() { return TEN.data(); }
  const double* g() const { return d_.t; }
  const double* x() const { return x_; }
  double* p() { return d_.p; }
  // A checkpoint copies the tension and the warm-start pressure down only when it is written.
  void outer_point(OuterPoint& at) {
    at.fetch = [this, &at] {
      at.tension.resize(n);
      at.inner.pressure.resize(n);
      TEN.download(at.tension.data(), n);
      d_.P.download(at.inner.pressure.data(), n);
      at.inner.penetration = delta_;
    };
  }
  bool solved() const { return have_p_; }
  // The total pressure p − t, the displacement w − h (w = hp + u, hp = h − G t: u − G t, as
  // on the CPU up to round-off) and the gap.
  void end(ContactState& st) {
    Field t(n);
    st.pressure.resize(n), st.displacement.resize(n), st.gap.resize(n);
    d_.P.download(st.pressure.data(), n);
    d_.W.download(st.displacement.data(), n);
    d_.T.download(st.gap.data(), n);
    TEN.download(t.data(), n);
    double *sp = st.pressure.data(), *su = st.displacement.data();
    const double* h = h_.data();
    Grid::parallel_for(n, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) sp[i] -= t[i], su[i] -= h[i];
    });
    st.penetration = delta_;
    pk::report_profile(d_);
  }

 private:
  // Counts the transforms of a scope with the half-space (the run's FFT pairs).
  using Counted = TransformTally<HalfSpace>;
  Counted counted() {
    return Counted(hs_, [this] { return d_.transforms(); });
  }

  HalfSpace& hs_;
  const Field& h_;
  const QuasiStaticAdhesion::Options& opt_;
  int nx_, ny_;
  qs::Stencil stencil_;
  double h_scale_;
  PolonskyKeer::Device d_;
  cuda::Buffer<double> H0, TEN, A;
  InnerSolves inner_;
  const double* x_ = nullptr;
  double delta_ = 0.0;
  bool have_p_ = false;
};

}  // namespace cmc::qs
