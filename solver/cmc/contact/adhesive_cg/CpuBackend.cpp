#include "cmc/contact/adhesive_cg/CpuBackend.hpp"

namespace cmc::adhesive {

void Sums::merge(const Sums& o) {
  uKu += o.uKu, phi += o.phi, nF += o.nF, sx += o.sx, sxx += o.sxx;
  sxHd += o.sxHd, sHd += o.sHd, sxd += o.sxd, sd += o.sd, gsum += o.gsum, changed += o.changed;
  rmax = std::max(rmax, o.rmax), out_abs = std::max(out_abs, o.out_abs);
  rmin = std::min(rmin, o.rmin), rmin_contact = std::min(rmin_contact, o.rmin_contact);
}

void DirSums::merge(const DirSums& o) {
  psid += o.psid, cd2 += o.cd2, dsum += o.dsum;
  dmax = std::max(dmax, o.dmax), afeas = std::min(afeas, o.afeas);
}

namespace {
template <bool Track>
DirSums direction_rows(const Arrays& A, const Shape& S, double mu, double ml, double beta, double m_old) {
  const double* __restrict x = A.x;
  const double* __restrict r = A.r;
  const double* __restrict c = A.c;
  double* __restrict d = A.d;
  unsigned char* __restrict bound = A.bound;
  return Grid::parallel_reduce<DirSums>(
      std::size_t(S.my),
      [&](std::size_t r0, std::size_t r1, DirSums& acc) {
        double psid = 0, cd2 = 0, dmax = 0, afeas = kInf, dsum = 0;
        for (std::size_t iy = r0; iy < r1; ++iy) {
          const std::size_t row = S.row(int(iy)), pe = S.patch_end(int(iy)), re = row + S.mx;
          for (std::size_t k = row; k < pe; ++k) {
            const double g = x[k];
            const double rk = r[k];
            const bool is_bound = g <= 0.0 && rk >= ml;
            if constexpr (Track) bound[k] = is_bound;
            double dk = 0.0;
            if (!is_bound) {
              const double psi = rk - mu;
              dk = -psi + beta * (d[k] - m_old);
              if (g <= 0.0 && dk < 0.0) dk = 0.0;  // feasible cone
              psid += psi * dk;
              cd2 += c[k] * dk * dk;
              dsum += dk;
              dmax = std::max(dmax, std::abs(dk));
              if (dk < 0.0) afeas = std::min(afeas, g / -dk);
            }
            d[k] = dk;
          }
          for (std::size_t k = pe; k < re; ++k) {  // padding: no wall, μ = 0
            const double dk = -r[k] + beta * d[k];
            psid += r[k] * dk;
            d[k] = dk;
          }
        }
        acc.merge({psid, cd2, dmax, afeas, dsum});
      },
      S.size());
}
}  // namespace

DirSums direction_pass(const Arrays& A, const Shape& S, double mu, double ml, double beta, double m_old, bool track) {
  return track ? direction_rows<true>(A, S, mu, ml, beta, m_old) : direction_rows<false>(A, S, mu, ml, beta, m_old);
}

double trial_pass(const Arrays& A, const Shape& S, double alpha, double* __restrict t) {
  const double* __restrict x = A.x;
  const double* __restrict d = A.d;
  return Grid::parallel_reduce<SumReduction>(
             std::size_t(S.my),
             [&](std::size_t r0, std::size_t r1, SumReduction& acc) {
               double gs = 0.0;
               for (std::size_t iy = r0; iy < r1; ++iy) {
                 const std::size_t row = S.row(int(iy)), pe = S.patch_end(int(iy)), re = row + S.mx;
                 for (std::size_t k = row; k < pe; ++k) {
                   const double g = std::max(x[k] + alpha * d[k], 0.0);
                   t[k] = g;
                   gs += g;
                 }
                 for (std::size_t k = pe; k < re; ++k) t[k] = x[k] + alpha * d[k];
               }
               acc.v += gs;
             },
             S.size())
      .v;
}

void displacement_of(double* __restrict x, const Shape& S, double s, double* __restrict u) {
  Grid::parallel_for(
      std::size_t(S.my),
      [&](std::size_t r0, std::size_t r1) {
        for (std::size_t iy = r0; iy < r1; ++iy) {
          const std::size_t row = S.row(int(iy)), pe = S.patch_end(int(iy)), re = row + S.mx;
          if (s != 1.0)
            for (std::size_t k = row; k < pe; ++k) x[k] *= s;
          for (std::size_t k = row; k < pe; ++k) u[k] = x[k] - (S.h[k] - S.delta);
          for (std::size_t k = pe; k < re; ++k) u[k] = x[k];
        }
      },
      S.size());
}

double patch_sum(const double* x, std::size_t n) {
  return Grid::parallel_reduce<SumReduction>(n, [&](std::size_t b, std::size_t e, SumReduction& acc) {
           double s = 0.0;
           for (std::size_t k = b; k < e; ++k) s += x[k];
           acc.v += s;
         }).v;
}

}  // namespace cmc::adhesive
