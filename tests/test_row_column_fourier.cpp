// RowColumnFourier (grid/RowColumnFourier.hpp): the 2-D transform made of 1-D transforms by
// rows and column blocks, into which the Polonsky-Keer iteration fuses its passes.
#include "cmc/grid/RowColumnFourier.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

using namespace cmc;

namespace {
using None = RowColumnFourier::None;
Field test_field(int nx, int ny) {
  Field f(std::size_t(nx) * ny);
  for (std::size_t i = 0; i < f.size(); ++i) f[i] = std::sin(0.37 * double(i)) + 0.1 * std::cos(0.011 * double(i * i % 977));
  return f;
}
}  // namespace

// The same modes as Fourier's 2-D r2c (found through index()), and back again: FFTW's
// transforms round differently, so they agree to round-off (1e-12 of the largest mode),
// not to the bit. Grids with a full last block, a narrow one, odd sides, rows that are not a
// multiple of the SIMD width (70: through the aligned row), and a single block.
TEST(RowColumnFourier, SameModesAsTheTwoDimensionalTransform) {
  for (auto [nx, ny] : std::vector<std::pair<int, int>>{{64, 64}, {62, 48}, {70, 33}, {17, 40}, {8, 8}, {256, 128}}) {
    SCOPED_TRACE(std::to_string(nx) + " x " + std::to_string(ny));
    const Field f = test_field(nx, ny);
    Fourier ref(nx, ny);
    ref.forward(f);
    RowColumnFourier rc(nx, ny);
    ASSERT_GE(rc.spectrum_size(), ref.spectrum_size());
    // The unused modes between the columns hold NaN: no transform may read them (the
    // modes found below would be NaN), and none may write them (checked at the end).
    Spectrum s(rc.spectrum_size(), Complex(std::nan(""), std::nan("")));
    std::vector<int> rows_seen(ny, 0);
    rc.forward_rows<None>(f.data(), s.data(), [&](std::size_t j, None&) { ++rows_seen[j]; });
    for (int j = 0; j < ny; ++j) EXPECT_EQ(rows_seen[j], 1) << "the row pass visits every row once";
    // The blocks may run on several threads: their mode counts travel in the sweep's partials.
    const double modes_seen = rc.columns<SumReduction>(s.data(), RowColumnFourier::kForward,
                                                       [&](const RowColumnFourier::Block& B, SumReduction& acc) {
                                                         EXPECT_EQ(B.rows, ny);
                                                         EXPECT_EQ(B.end - B.begin, std::size_t(B.width) * B.stride);
                                                         B.each([&](std::size_t) { acc.v += 1.0; });
                                                       }).v;
    EXPECT_EQ(modes_seen, double(ref.spectrum_size())) << "each() visits every mode once";
    const auto spec = ref.spectrum();
    double peak = 0.0, err = 0.0;
    for (int iqy = 0; iqy < ny; ++iqy)
      for (int iqx = 0; iqx <= nx / 2; ++iqx) {
        const Complex a = spec[std::size_t(iqy) * std::size_t(nx / 2 + 1) + std::size_t(iqx)], b = s[rc.index(iqx, iqy)];
        peak = std::max(peak, std::abs(a));
        err = std::max(err, std::abs(a - b));
      }
    EXPECT_LT(err, 1e-12 * peak);
    // Inverse: unnormalised, so f times the number of points; the spectrum is kept.
    const Spectrum kept = s;
    Field back(f.size());
    rc.columns<None>(s.data(), RowColumnFourier::kInverse, [](const RowColumnFourier::Block&, None&) {});
    const Spectrum half = s;
    rc.inverse_rows<None>(s.data(), back.data(), [](std::size_t, None&) {});
    EXPECT_EQ(half.size(), s.size());
    for (std::size_t k = 0; k < s.size(); ++k) {
      if (std::isnan(half[k].real())) continue;  // an unused mode: NaN != NaN
      ASSERT_EQ(half[k], s[k]) << "inverse_rows leaves its spectrum as it is";
    }
    std::size_t unused = 0;
    for (const Complex& v : s) unused += std::isnan(v.real()) && std::isnan(v.imag());
    EXPECT_EQ(unused, rc.spectrum_size() - ref.spectrum_size()) << "the transforms left the unused modes alone";
    double ferr = 0.0;
    for (std::size_t i = 0; i < f.size(); ++i) ferr = std::max(ferr, std::abs(back[i] / double(f.size()) - f[i]));
    EXPECT_LT(ferr, 1e-13);
    EXPECT_EQ(rc.forward_count(), 1);
    EXPECT_EQ(rc.inverse_count(), 1);
    EXPECT_GT(rc.seconds(), 0.0);
  }
}

// reorder() writes a multiplier of Fourier's row layout in the block layout: every mode's
// value lands at index(iqx, iqy).
TEST(RowColumnFourier, ReorderPutsEveryModeAtItsIndex) {
  const int nx = 70, ny = 12, nq = nx / 2 + 1;
  RowColumnFourier rc(nx, ny);
  Field rows(std::size_t(nq) * ny), blocks(rc.spectrum_size(), -1.0);
  for (std::size_t k = 0; k < rows.size(); ++k) rows[k] = double(k);
  rc.reorder(rows.data(), blocks.data());
  for (int iqy = 0; iqy < ny; ++iqy)
    for (int iqx = 0; iqx < nq; ++iqx) EXPECT_EQ(blocks[rc.index(iqx, iqy)], double(iqy * nq + iqx));
}

// Sweeps reduce in a fixed order: the same sums, to the bit, on a rerun.
TEST(RowColumnFourier, SweepsReduceTheSameOnARerun) {
  const int n = 256;  // 65536 points: the sweeps run on every thread
  const Field f = test_field(n, n);
  RowColumnFourier rc(n, n);
  auto run = [&] {
    Spectrum s(rc.spectrum_size());
    const SumReduction rows = rc.forward_rows<SumReduction>(f.data(), s.data(), [&](std::size_t j, SumReduction& a) {
      for (int i = 0; i < n; ++i) a.v += f[j * n + i] * f[j * n + i];
    });
    const SumReduction modes = rc.columns<SumReduction>(s.data(), RowColumnFourier::kForward, [&](const RowColumnFourier::Block& B, SumReduction& a) {
      B.each([&](std::size_t k) { a.v += std::norm(s[k]); });
    });
    return std::pair{rows.v, modes.v};
  };
  const auto a = run(), b = run();
  EXPECT_EQ(a.first, b.first);
  EXPECT_EQ(a.second, b.second);
}

// A grid it cannot transform (a line, no points) is refused with a message that says why.
TEST(RowColumnFourier, RefusesALineOrAnEmptyGrid) {
  for (auto [nx, ny] : std::vector<std::pair<int, int>>{{64, 1}, {0, 8}, {8, 0}}) {
    try {
      RowColumnFourier rc(nx, ny);
      ADD_FAILURE() << nx << " x " << ny << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("two-dimensional"), std::string::npos) << e.what();
    }
  }
}

// Where its plans came from, as summary.json reports it (grid.fft_plans, after the
// half-space's own): the built-in wisdom holds square grids' rows and column blocks from 8
// to the build's largest (4096 by default); a side it does not hold gets FFTW_ESTIMATE
// plans, and says so. Under the default planner only ($CMC_FFTW_PLANNER unset).
TEST(RowColumnFourier, SaysWhereItsPlansCameFrom) {
  if (const char* p = std::getenv("CMC_FFTW_PLANNER"); p && std::string(p) != "builtin") GTEST_SKIP() << p;
  EXPECT_EQ(RowColumnFourier(256, 256).plan_source(), "built-in wisdom");
  EXPECT_EQ(RowColumnFourier(240, 240).plan_source(), "estimate");
}
