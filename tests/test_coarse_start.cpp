// The prolongation of a coarser run's state (output/CoarseStart.hpp): periodic bilinear,
// exact where it should be. The start as a whole (files, checks, the state it ends in) is
// tests/start_from_test.py's.
#include "cmc/output/CoarseStart.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using namespace cmc;

TEST(CoarseStart, ProlongKeepsSharedPointsAndIsBilinearBetween) {
  const int cnx = 6, cny = 4, m = 3;
  Field c(std::size_t(cnx) * cny);
  for (int j = 0; j < cny; ++j)
    for (int i = 0; i < cnx; ++i) c[std::size_t(j) * cnx + i] = std::sin(1.0 + i) + 0.3 * std::cos(2.0 * j) + 0.1 * i * j;
  const Field f = prolong(c, cnx, cny, m);
  const int nx = cnx * m, ny = cny * m;
  ASSERT_EQ(f.size(), std::size_t(nx) * ny);
  for (int iy = 0; iy < ny; ++iy)
    for (int ix = 0; ix < nx; ++ix) {
      const int i0 = ix / m, j0 = iy / m, i1 = (i0 + 1) % cnx, j1 = (j0 + 1) % cny;  // periodic
      const double fx = double(ix % m) / m, fy = double(iy % m) / m;
      auto at = [&](int i, int j) { return c[std::size_t(j) * cnx + i]; };
      const double want = (1 - fx) * (1 - fy) * at(i0, j0) + fx * (1 - fy) * at(i1, j0) + (1 - fx) * fy * at(i0, j1) +
                          fx * fy * at(i1, j1);
      ASSERT_NEAR(f[std::size_t(iy) * nx + ix], want, 1e-14) << ix << "," << iy;
      if (ix % m == 0 && iy % m == 0) ASSERT_EQ(f[std::size_t(iy) * nx + ix], at(i0, j0));  // shared points: exact
    }
}

TEST(CoarseStart, ProlongByOneIsTheIdentityAndRefusesAMismatch) {
  Field c{1.0, 2.0, 3.0, 4.0, 5.0, 6.0};
  EXPECT_EQ(prolong(c, 3, 2, 1), c);
  EXPECT_THROW(prolong(c, 4, 2, 2), std::invalid_argument);
  EXPECT_THROW(prolong(c, 3, 2, 0), std::invalid_argument);
}

TEST(CoarseStart, ProlongIsExactOnALinearRampWithinThePeriod) {
  // A field linear in x between coarse points (no wrap inside a cell): reproduced exactly.
  const int cnx = 5, cny = 1, m = 4;
  Field c{0.0, 1.0, 2.0, 3.0, 4.0};
  const Field f = prolong(c, cnx, cny, m);
  for (int ix = 0; ix < (cnx - 1) * m; ++ix) EXPECT_NEAR(f[ix], double(ix) / m, 1e-15);
  // the last cell wraps to the first point: from 4 back down to 0
  EXPECT_NEAR(f[(cnx - 1) * m + 2], 2.0, 1e-15);
}
