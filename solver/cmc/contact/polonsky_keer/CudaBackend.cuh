#pragma once
// The device backend of Polonsky-Keer (Iteration.hpp; its contract: Contract.hpp) on one
// GPU: its fields and passes, shared by polonsky_keer/CudaBackend.cu (the hard-wall solve)
// and quasi_static/CudaBackend.cu (the quasi-static solver's outer step, which keeps its
// own fields beside these). Included by .cu files only (and by the host emulation's tests,
// tests/emulation). The combined operations are compose::'s (Compose.hpp): a step makes w
// with the CPU's per-point parts (Parts.hpp), and no spectrum of p or of h is held.
//
// Device memory, per point of an n-point grid (nspec = ny (nx/2 + 1) ≈ n/2 modes):
// p, w = h + u, t, h and G t of a linear step (5 doubles), z (1, with the preconditioner),
// the contact mask (1 byte), the transform's scratch spectrum, which holds t̂ too (nspec
// complex ≈ 1 double), the compliance (nspec doubles ≈ ½; the preconditioner's stiffness
// is taken from it), and cuFFT's work area (cufftMakePlan2d reports it for the shape).
// Counted by pk::device_bytes (Memory.hpp), with the work area taken as one real field:
// 17.3 GiB at 16384² with the preconditioner, 69 GiB at 32768² (61 GiB without). An
// earlier layout that held p̂, ĥ/N, t̂ and the stiffness as spectra of their own counted
// 22.3 GiB at 16384², and nvidia-smi's peak on an H100 was 22.8 GiB with the CUDA context.
#include "cmc/contact/polonsky_keer/Compose.hpp"
#include "cmc/contact/polonsky_keer/Iteration.hpp"
#include "cmc/grid/CudaDevice.cuh"

#include <cstdio>
#include <sstream>

namespace cmc {

struct PolonskyKeer::Device : pk::Fields {
  // ---- the backend of pk::Run (Contract.hpp, PolonskyKeerBackend): the fields
  // (pk::Fields), the passes and the transforms

  template <class F>
  void all(std::size_t k, F f) {
    cuda::all(k, f);
  }
  template <class Acc, class F>
  Acc reduce_in(const std::uint8_t* mask, std::size_t k, F f) {
    return reducer.run<Acc>(k, cuda::InMask{mask}, f);
  }
  template <class Acc, class F>
  Acc reduce_in_or_below(const std::uint8_t* mask, const double* v, double level, std::size_t k, F f) {
    return reducer.run<Acc>(k, cuda::InMaskOrBelow{mask, v, level}, f);
  }
  double sum(const double* v) {
    return reducer.run<Sum>(n, cuda::Everywhere{}, [=] __device__(std::size_t i, Sum& a) { a.v += v[i]; }).v;
  }
  // The transforms of compose:: (Contract.hpp, TransformParts).
  void forward_p() { fft.forward(p, out); }
  double curvature_t() {
    fft.forward(t, out);
    return quadratic_form(out, ker);
  }
  void inverse_w() { fft.inverse(out, w); }
  void inverse_gt() { fft.inverse(out, gt); }
  // The stiffness taken from the compliance (Parts.hpp) instead of held (half a spectrum,
  // 4 GiB at 32768²). It may differ from the CPU's unfused E*|q|/(2N) in the last bit.
  void stiffness_z() {
    fft.forward(z, out);
    double* o = out;
    const double* k = ker;
    const double nn = 1.0 / (transform_points * transform_points);
    cuda::all(nspec, [=] __device__(std::size_t j) {
      const double s = pk::stiffness_from_compliance(k[j], nn);
      o[2 * j] *= s, o[2 * j + 1] *= s;
    });
    fft.inverse(out, z);
  }
  // The combined operations, their parts one after the other (kernels and cuFFT calls).
  template <class Acc, class F>
  Acc direction_and_curvature(const std::uint8_t* mask, F f, double& curvature) {
    return pk::compose::direction_and_curvature<Acc>(*this, mask, f, curvature);
  }
  template <class Acc, class F>
  Acc exact_and_gap_sums(double s, const std::uint8_t* mask, double level, F f) {
    return pk::compose::exact_and_gap_sums<Acc>(*this, s, mask, level, f);
  }
  template <class Acc, class F>
  Acc linear_and_gap_sums(double s, double tau, const std::uint8_t* mask, double level, F f) {
    return pk::compose::linear_and_gap_sums<Acc>(*this, s, tau, mask, level, f);
  }
  template <class Acc, class StepAcc, class P, class C, class F>
  Acc project_and_gap_sums(P pass, C choose, bool, const std::uint8_t* mask, double level, F f, StepAcc& st,
                           pk::StepChoice& c) {
    return pk::compose::project_and_gap_sums<Acc>(*this, pass, choose, mask, level, f, st, c);
  }
  template <class Acc, class Fill, class F>
  Acc stiffness_and_sums(Fill fill, const std::uint8_t* mask, F f) {
    return pk::compose::stiffness_and_sums<Acc>(*this, fill, mask, f);
  }
  // Σ_q weight(q) mult(q) |s_q|² over the r2c half-spectrum (HalfSpace::quadratic_form).
  double quadratic_form(const double* s, const double* mult) {
    const int cols = nx / 2 + 1, nxx = nx;
    return reducer
        .run<Sum>(nspec, cuda::Everywhere{},
                      [=] __device__(std::size_t j, Sum& a) {
                        const int c = int(j % std::size_t(cols));
                        const double wgt = (c == 0 || 2 * c == nxx) ? 1.0 : 2.0;
                        a.v += wgt * mult[j] * (s[2 * j] * s[2 * j] + s[2 * j + 1] * s[2 * j + 1]);
                      })
        .v;
  }

  // ---- the buffers
  int nx, ny;
  bool precondition;
  cuda::Buffer<double> P, W, T, Z, H, GT, OUT, KER;
  cuda::Buffer<std::uint8_t> M;
  cuda::Reducer reducer;
  cuda::Fft fft;

  Device(HalfSpace& hs, bool pre)
      : pk::Fields{hs.grid().size(), hs.spectrum_size(), double(hs.grid().points()), double(hs.transform_points())},
        nx(hs.grid().nx), ny(hs.grid().ny), precondition(pre), P(n, "the pressure"), W(n, "the displacement"),
        T(n, "the direction"), Z(pre ? n : 0, "the preconditioned gap"), H(n, "the heights"),
        GT(n, "G t"), OUT(2 * nspec, "a spectrum"), KER(nspec, "the compliance"),
        M(n, "the contact set"), fft(nx, ny) {
    p = P.data(), w = W.data(), t = T.data(), z = Z.data(), m = M.data(), h = H.data();
    gt = GT.data(), out = OUT.data(), ker = KER.data();
    KER.upload(hs.compliance().data(), nspec);
  }
  // The device's transforms so far (TransformTally).
  TransformCounts transforms() const { return {fft.forwards, fft.inverses, fft.seconds}; }
};

namespace pk {
// With $CMC_CUDA_PROFILE set: where the device's time went so far, on stderr.
void report_profile(const PolonskyKeer::Device& d);
// Polonsky-Keer on the device's fields (pk::iterate over the device backend). Defined in
// polonsky_keer/CudaBackend.cu alone, so that one translation unit instantiates the iteration's
// __host__ __device__ lambdas (why: the note there); other units call this.
End run_on_device(PolonskyKeer::Device& d, const PolonskyKeer::Options& o, double h_scale, const Target& target,
                  const Start& start, SolveResult& res);
// Throws, naming the grid and the GiB, where `need` bytes exceed the device's free memory;
// returns the free bytes.
std::size_t check_device_memory(const char* who, int nx, int ny, std::size_t need);
}  // namespace pk

}  // namespace cmc
