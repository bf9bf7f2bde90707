// Build step: plan cmc's FFTs once with FFTW_MEASURE and write the wisdom into a C++
// source file that is compiled into the library (grid/Grid.cpp imports it at start).
//
// Why: FFTW_MEASURE times candidate algorithms and keeps the fastest, so two plannings of
// the same transform can pick different algorithms, which round differently; on a
// multistable problem (adhesion on a coarse grid) that round-off selects another local
// minimum. With the wisdom fixed at build time and never re-measured at run time, every
// run of a build uses the same plans: the same bits on every rerun, with or without a
// wisdom file, and no planning time on a first run. Transforms not planned here fall back
// to FFTW_ESTIMATE, which is deterministic too (see Grid.hpp).
//
// The transforms planned are the ones cmc makes (Fourier in grid/Grid.cpp): out-of-place
// r2c and c2r on FFTW-aligned arrays, square 2-D grids of 2^k points per side (the
// periodic grids and the zero-padded free-boundary grids of the case files) and 1-D
// lines, with the thread counts cmc uses (one below 2^16 points, else each of 1, 2 and
// the hardware's); and the column transforms of RowColumnFourier (grid/RowColumnFourier.hpp,
// the Polonsky-Keer iteration's fused transform), whose rows are the 1-D lines, on one
// thread, for the same square grids.
//
// usage: cmc_make_wisdom OUTPUT.cpp [max points per side, default 4096]
#include "cmc/grid/ColumnBlockPlans.hpp"

#include <fftw3.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <set>
#include <string>
#include <thread>

namespace {

void plan_pair(int nx, int ny, int threads) {
  const std::size_t n = std::size_t(nx) * std::size_t(ny), nc = std::size_t(nx / 2 + 1) * std::size_t(ny);
  double* r = fftw_alloc_real(n);
  fftw_complex* c = fftw_alloc_complex(nc);
  fftw_plan_with_nthreads(threads);
  fftw_plan f = ny == 1 ? fftw_plan_dft_r2c_1d(nx, r, c, FFTW_MEASURE) : fftw_plan_dft_r2c_2d(ny, nx, r, c, FFTW_MEASURE);
  fftw_plan b = ny == 1 ? fftw_plan_dft_c2r_1d(nx, c, r, FFTW_MEASURE) : fftw_plan_dft_c2r_2d(ny, nx, c, r, FFTW_MEASURE);
  fftw_destroy_plan(f);
  fftw_destroy_plan(b);
  fftw_free(r);
  fftw_free(c);
}

// RowColumnFourier's plans for an nx x ny grid: its rows (1-D lines, one thread), and its
// column blocks, full and the last one.
void plan_column_blocks(int nx, int ny) {
  plan_pair(nx, 1, 1);
  const int nq = nx / 2 + 1, full = std::min(nq, cmc::detail::kColumnBlock);
  const int last = nq - (nq - 1) / cmc::detail::kColumnBlock * cmc::detail::kColumnBlock;
  fftw_complex* blk = fftw_alloc_complex(std::size_t(cmc::detail::kColumnBlock) * std::size_t(ny + cmc::detail::kColumnPad));
  fftw_plan_with_nthreads(1);
  for (int width : {full, last})
    for (int sign : {FFTW_FORWARD, FFTW_BACKWARD}) fftw_destroy_plan(cmc::detail::plan_column_block(ny, width, blk, sign, FFTW_MEASURE));
  fftw_free(blk);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: cmc_make_wisdom OUTPUT.cpp [max points per side]\n");
    return 2;
  }
  const int max_side = argc > 2 ? std::atoi(argv[2]) : 4096;
  fftw_init_threads();
  const int hw = int(std::max(1u, std::thread::hardware_concurrency()));
  const std::set<int> thread_counts{1, std::min(2, hw), hw};
  // Grid.cpp's rule: transforms below 2^16 points run on one thread.
  auto plan_all = [&](int nx, int ny) {
    if (std::size_t(nx) * ny < (std::size_t(1) << 16)) return plan_pair(nx, ny, 1);
    for (int t : thread_counts) plan_pair(nx, ny, t);
  };
  for (int n = 8; n <= max_side; n *= 2) plan_all(n, n);
  for (int n = 8; n <= max_side; n *= 2) plan_column_blocks(n, n);
  for (int n = 64; n <= 65536; n *= 2) plan_all(n, 1);
  char* w = fftw_export_wisdom_to_string();
  std::ofstream out(argv[1]);
  out << "// Generated at build time by solver/tools/make_wisdom.cpp: FFTW wisdom (FFTW_MEASURE)\n"
         "// for square grids up to " << max_side << " points per side (and their column blocks) and\n"
         "// 1-D lines up to 65536.\n"
         "namespace cmc::detail {\nextern const char* const kBuiltinWisdom;\n"
         "const char* const kBuiltinWisdom = R\"cmcwisdom(" << w << ")cmcwisdom\";\n}\n";
  fftw_free(w);
  if (!out) {
    std::fprintf(stderr, "cmc_make_wisdom: could not write %s\n", argv[1]);
    return 1;
  }
  return 0;
}
