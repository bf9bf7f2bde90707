// The grid layer is the only place that reduces whole fields or runs threads: a
// distributed (MPI) or GPU backend replaces it without touching the solvers. These tests
// check its reductions, and check the sources for a reduction written beside it.
#include "cmc/grid/Grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

using namespace cmc;
namespace fs = std::filesystem;

namespace {

// Runs f with CMC_THREADS set to `threads`, restoring the previous value.
template <class F>
void with_threads(const char* threads, F f) {
  const char* old = std::getenv("CMC_THREADS");
  const std::string saved = old ? old : "";
  setenv("CMC_THREADS", threads, 1);
  f();
  if (old) setenv("CMC_THREADS", saved.c_str(), 1);
  else unsetenv("CMC_THREADS");
}

Field ramp(std::size_t n) {
  Field f(n);
  for (std::size_t i = 0; i < n; ++i) f[i] = 1.0 / double(i + 1) - 1e-3 * double(i % 7);
  return f;
}

double chunked_sum(const Field& f) {
  return Grid::parallel_reduce<SumReduction>(f.size(), [&](std::size_t b, std::size_t e, SumReduction& acc) {
           double s = 0.0;
           for (std::size_t i = b; i < e; ++i) s += f[i];
           acc.v += s;
         }).v;
}

}  // namespace

TEST(GridLayer, ReductionsAgreeWithDirectLoops) {
  const Field a = ramp(1000), b = ramp(1000);
  double s = 0.0, d = 0.0, mx = -1e300, mn = 1e300;
  std::size_t above = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    s += a[i], d += a[i] * b[i], mx = std::max(mx, a[i]), mn = std::min(mn, a[i]);
    above += a[i] > 0.1;
  }
  EXPECT_NEAR(Grid::sum(a), s, 1e-13 * std::abs(s));
  EXPECT_EQ(Grid::dot(a, b), d);  // same order of additions
  EXPECT_EQ(Grid::max(a), mx);
  EXPECT_EQ(Grid::min(a), mn);
  EXPECT_EQ(Grid::count_if(a, [](double v) { return v > 0.1; }), above);
  std::vector<std::uint8_t> mask(77, 0);
  for (std::size_t i = 0; i < mask.size(); i += 3) mask[i] = 1;
  EXPECT_EQ(Grid::count(mask), std::size_t(26));
}

// parallel_reduce: one chunk per thread, partials merged in chunk order, so a rerun at the
// same thread count gives the same bits, and one thread is exactly the serial loop.
TEST(GridLayer, ParallelReduceIsDeterministic) {
  const Field f = ramp(std::size_t(1) << 17);  // above Grid::parallel_min: threads are used
  double serial = 0.0;
  for (double v : f) serial += v;
  with_threads("1", [&] { EXPECT_EQ(chunked_sum(f), serial); });
  with_threads("2", [&] {
    const double a = chunked_sum(f), b = chunked_sum(f);
    EXPECT_EQ(a, b);
    // Two chunks, merged in order: exactly (first half) + (second half).
    double lo = 0.0, hi = 0.0;
    for (std::size_t i = 0; i < f.size() / 2; ++i) lo += f[i];
    for (std::size_t i = f.size() / 2; i < f.size(); ++i) hi += f[i];
    EXPECT_EQ(a, (0.0 + lo) + hi);
  });
}

// No reduction beside the grid layer: outside solver/cmc/grid/, no OpenMP pragma (threads
// and the combination of partial results are the grid layer's), no hand-written hook to a
// distributed backend, and no std::accumulate/std::reduce over a field. A pass with
// partial results uses Grid::parallel_reduce; a plain sum, Grid::sum.
TEST(GridLayer, NoReductionOutsideTheGridLayer) {
  const fs::path root = fs::path(CMC_SOURCE_DIR);
  // Threads, hooks to a distributed backend, library reductions; and a loop over a whole
  // field (range-for by value, or an index loop from 0) whose body accumulates a scalar.
  const std::regex forbidden(
      R"(#\s*pragma\s+omp|allreduce|MPI_|std::accumulate|std::reduce\b)"
      R"(|for\s*\(\s*(const\s+)?(double|float|auto|int|long|std::uint8_t|unsigned char)\s+\w+\s*:\s*[^)]*\)\s*\w+\s*\+=)"
      R"(|for\s*\(\s*(std::size_t|int|long|std::ptrdiff_t)\s+\w+\s*=\s*0\s*;\s*\w+\s*<\s*(\w+\.size\(\)|n|n_)\s*;[^)]*\)\s*\w+\s*\+=)");
  std::vector<std::string> hits;
  for (const char* dir : {"solver", "validation"}) {
    for (const auto& e : fs::recursive_directory_iterator(root / dir)) {
      const fs::path& p = e.path();
      if (!e.is_regular_file() || (p.extension() != ".cpp" && p.extension() != ".hpp")) continue;
      if (p.parent_path() == root / "solver" / "cmc" / "grid") continue;
      std::ifstream in(p);
      std::string line;
      for (int no = 1; std::getline(in, line); ++no) {
        const auto c = line.find("//");
        const std::string code = c == std::string::npos ? line : line.substr(0, c);
        if (std::regex_search(code, forbidden)) hits.push_back(p.string() + ":" + std::to_string(no) + ": " + line);
      }
    }
  }
  std::ostringstream msg;
  for (const auto& h : hits) msg << "\n  " << h;
  EXPECT_TRUE(hits.empty()) << "reductions or threads beside the grid layer (use Grid::parallel_reduce):" << msg.str();
}

// Fields and spectra of 16 MiB and more start on a 2 MiB boundary (whole transparent huge
// pages, grid/Grid.cpp); smaller ones keep fftw_malloc's SIMD alignment. Both read back what was
// written, across the size where the allocator changes.
TEST(GridLayer, LargeArraysStartOnHugePages) {
  const std::size_t huge = std::size_t(2) << 20;
  for (std::size_t n : {std::size_t(1000), huge - 1, huge, huge + 3}) {  // doubles: 16 MiB = huge doubles
    Field f(n);
    for (std::size_t i = 0; i < n; i += 4097) f[i] = double(i);
    const auto at = reinterpret_cast<std::uintptr_t>(f.data());
    EXPECT_EQ(at % 16, 0u) << n;  // SIMD alignment (FFTW needs 16 bytes at least)
    if (n * sizeof(double) >= 16 * (std::size_t(1) << 20)) EXPECT_EQ(at % huge, 0u) << n << " doubles";
    for (std::size_t i = 0; i < n; i += 4097) ASSERT_EQ(f[i], double(i));
  }
}

// Fourier::scratch (the fused Polonsky-Keer sweeps' longer spectrum): the buffer grows,
// spectrum() keeps its length, and the transforms go on in the moved buffer with the same
// bits; a smaller request keeps it where it is.
TEST(GridLayer, FourierScratchGrowsAndTransformsGoOn) {
  const int n = 64;
  Fourier f(n, n);
  Field x(std::size_t(n) * n), y(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.37 * double(i));
  f.forward(x);
  const std::vector<Complex> before(f.spectrum().begin(), f.spectrum().end());
  const std::size_t size = f.spectrum_size();
  Complex* s = f.scratch(size + 1000);
  EXPECT_EQ(f.spectrum().data(), s);
  EXPECT_EQ(f.spectrum().size(), size);
  EXPECT_EQ(f.scratch(10), s) << "a smaller request keeps the buffer";
  f.forward(x);
  EXPECT_TRUE(std::equal(before.begin(), before.end(), f.spectrum().begin())) << "the same modes, to the bit";
  f.inverse(y);
  for (std::size_t i = 0; i < x.size(); ++i) ASSERT_NEAR(y[i] / double(x.size()), x[i], 1e-13);
}
