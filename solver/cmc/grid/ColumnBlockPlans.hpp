// The column transforms of RowColumnFourier (grid/RowColumnFourier.hpp), in a header of
// their own so that the build step that plans cmc's FFTs into the built-in wisdom
// (solver/tools/make_wisdom.cpp) plans exactly the transforms the library asks for.
//
// A block of `width` spectrum columns is stored as ny rows of `width` complex numbers, one
// after the other; its column transforms are `width` complex DFTs of length ny, in place,
// with stride `width` and distance 1 (FFTW vectorises across the columns). Planned with one
// thread: RowColumnFourier runs blocks in parallel itself.
#pragma once

#include <fftw3.h>

namespace cmc::detail {

// Spectrum columns per block: 8 complex doubles are 128 bytes (two cache lines) a row, so
// a block of a 4096-row grid is 512 KiB, and the passes that map one spectrum's block onto
// another's between the forward and the inverse transforms (the Polonsky-Keer step, 2048²:
// two blocks of 256 KiB) keep both in a core's L2 (1 MiB on the 2-core CI machine). 16
// columns, before 2026-11-28, put two 512 KiB blocks there at 2048² and filled it; 8 took
// 2-4 % off an iteration at 2048² and 5 % at 4096², 4 was slower than 8 (issue 11; README,
// "Performance").
inline constexpr int kColumnBlock = 8;

// The plan of one block's column transforms (sign FFTW_FORWARD or FFTW_BACKWARD) on
// `block` (FFTW-aligned, ny * width complex numbers); nullptr if FFTW made none (with
// FFTW_WISDOM_ONLY: no wisdom for it). The caller sets fftw_plan_with_nthreads(1).
inline fftw_plan plan_column_block(int ny, int width, fftw_complex* block, int sign, unsigned flags) {
  int n[1] = {ny};
  return fftw_plan_many_dft(1, n, width, block, nullptr, width, 1, block, nullptr, width, 1, sign, flags);
}

}  // namespace cmc::detail
