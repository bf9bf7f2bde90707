// The column transforms of RowColumnFourier (grid/RowColumnFourier.hpp), in a header of
// their own so that the build step that plans cmc's FFTs into the built-in wisdom
// (solver/tools/make_wisdom.cpp) plans exactly the transforms the library asks for.
//
// A block of `width` spectrum columns is stored as `width` columns of ny complex numbers,
// kColumnPad apart (the distance from one column's start to the next is ny + kColumnPad);
// its column transforms are `width` contiguous complex DFTs of length ny, in place.
// Planned with one thread: RowColumnFourier runs blocks in parallel itself.
#pragma once

#include <fftw3.h>

namespace cmc::detail {

// Spectrum columns per block: a block of 8 columns of a 4096-row grid is 512 KiB, and the
// passes that map one spectrum's block onto another's between the forward and the inverse
// transforms (the Polonsky-Keer step, 2048²: two blocks of 256 KiB) keep both in a core's
// L2 (1 MiB on the 2-core CI machine). 16 columns put two 512 KiB blocks there at 2048² and
// filled it; 8 took 2-4 % off an iteration at 2048² and 5 % at 4096², 4 was slower than 8
// (docs/developer/decisions.md).
inline constexpr int kColumnBlock = 8;

// Modes left unused after each column (128 bytes). Without them the columns of a 2^k-row
// grid start 2^k × 16 bytes apart, the same offset in every 64 KiB at ny ≥ 4096, so the
// chunks that RowColumnFourier's gather reads for one group of rows (two cache lines in
// each of 2056 columns at 4096²) all fall into the same few sets of the L2 cache and
// evict each other before they are used. With 8 they tile the sets. BM_RowColumnPair
// (FFTW_MEASURE at run time, best of 5, three rounds, 2 threads): 4096² 61-66 ms with 8
// against 82-95 ms without, and 72 ms for the earlier layout of ny rows of 8 modes; 2048²
// 14-16 ms, 15-16 ms without, 15.3-15.6 ms for the earlier layout. 16 gave the same as 8.
inline constexpr int kColumnPad = 8;

// The plan of one block's column transforms (sign FFTW_FORWARD or FFTW_BACKWARD) on
// `block` (FFTW-aligned, width columns of ny complex numbers, column c at c (ny + kColumnPad)); nullptr if FFTW made none (with
// FFTW_WISDOM_ONLY: no wisdom for it). The caller sets fftw_plan_with_nthreads(1).
inline fftw_plan plan_column_block(int ny, int width, fftw_complex* block, int sign, unsigned flags) {
  int n[1] = {ny};
  const int ld = ny + kColumnPad;
  return fftw_plan_many_dft(1, n, width, block, nullptr, 1, ld, block, nullptr, 1, ld, sign, flags);
}

}  // namespace cmc::detail
