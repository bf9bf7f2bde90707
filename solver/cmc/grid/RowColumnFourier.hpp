// A 2-D real transform of a whole periodic nx × ny grid made of FFTW's 1-D transforms, so
// that a solver's per-point passes can run inside the transform's sweeps while the data
// are in cache: a pass over a row right before that row's r2c transform or right
// after its c2r transform, and a pass over modes between a block's forward and inverse
// column transforms.
//
// Why: a Polonsky-Keer iteration is an FFT pair plus about eight passes over the grid; run
// one after the other they cost 0.7 of a pair on top of it at 2048² (perf: a quarter of the
// time in the passes, the rest in FFTW, whose 2-D plans copy columns through buffers).
// A 2-D transform is the row transforms followed by the column transforms (Cooley &
// Tukey's row-column method; Van Loan, Computational Frameworks for the FFT (1992), §3.3):
// here the columns are kept as blocks of kColumnBlock spectrum columns, each block's
// ny × width modes contiguous, so the column transforms of a block, and any pass over its
// modes, touch one piece of memory that fits in a core's cache.
//
// Layout of a spectrum ("column blocks"): the nq = nx/2 + 1 columns of the r2c spectrum
// split into blocks of kColumnBlock (the last one narrower); block b holds its columns
// [b kColumnBlock, b kColumnBlock + width) one after the other, each as ny contiguous
// modes followed by kColumnPad unused ones (ColumnBlockPlans.hpp says why), so that a
// column's transform is FFTW's contiguous one. (With a block of ny rows of width modes
// FFTW transformed strided columns through a buffer of its own, and a block's column pair
// took 75 µs at 2048² against 62 µs contiguous, FFTW 3.3.10, FFTW_MEASURE, 2 cores.) spectrum_size() is nq (ny + kColumnPad), more than
// Fourier's nq ny: a buffer for this layout is that long. The unused modes are neither
// read nor written by the transforms, and passes reach the modes through Block::each().
// index() finds a mode.
//
// Sweeps (each runs on the threads of Grid::parallel_reduce: rows, or blocks, in contiguous
// ranges per thread, partial results merged in thread order, so a rerun with the same
// thread count gives the same bits; the transforms of a row or a block do not depend on
// the thread count at all):
//   forward_rows(f, s, pass):  for each row j: pass(j, acc), then s's row j = r2c of f's
//   forward_rows_from(s, pass): for each row j: pass(j, row, acc) writes row j's values
//                              into a buffer of the thread's, then s's row j = r2c of it
//   columns(s, what, pass, s2): for each block: forward column transforms (what & kForward),
//                              pass(block, acc), inverse column transforms (what & kInverse)
//                              of s, or of s2 if given (a pass that maps one spectrum onto
//                              another between the two transforms)
//   inverse_rows(s, f, pass):  for each row j: f's row j = c2r of s's row j, then pass(j, acc)
//   inverse_rows_through(s, pass): for each row j: pass(j, row, acc) with row = c2r of s's
//                              row j in a buffer of the thread's
// A forward transform is forward_rows then columns(kForward); an inverse one columns(kInverse)
// then inverse_rows. Both unnormalised, as Fourier's. s is left as it is by inverse_rows.
// Plans: the built-in wisdom's (solver/tools/make_wisdom.cpp plans these transforms too),
// else FFTW_ESTIMATE, under the same $CMC_FFTW_PLANNER rules as Fourier.
#pragma once

#include "cmc/grid/Grid.hpp"

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

namespace cmc {

class RowColumnFourier {
 public:
  enum : int { kForward = 1, kInverse = 2 };
  static constexpr int kWidth = 8;  // columns per block (ColumnBlockPlans.hpp)
  // One block's memory [begin, end): columns [iqx0, iqx0 + width) of all `rows` rows, mode
  // (iqx0 + c, iqy) at begin + c * stride + iqy (stride = rows + kColumnPad; the modes in
  // between are unused). each(f) calls f(k) for the block's modes, column by column.
  struct Block {
    std::size_t begin = 0, end = 0, stride = 0;
    int iqx0 = 0, width = 0, rows = 0;
    template <class F>
    void each(F&& f) const {
      for (int c = 0; c < width; ++c) {
        const std::size_t k0 = begin + std::size_t(c) * stride, k1 = k0 + std::size_t(rows);
        for (std::size_t k = k0; k < k1; ++k) f(k);
      }
    }
  };

  RowColumnFourier(int nx, int ny);
  ~RowColumnFourier();
  RowColumnFourier(const RowColumnFourier&) = delete;
  RowColumnFourier& operator=(const RowColumnFourier&) = delete;

  int nx() const { return nx_; }
  int ny() const { return ny_; }
  // Complex numbers in a spectrum of this layout (unused modes included).
  std::size_t spectrum_size() const { return std::size_t(nq_) * ld_; }
  int blocks() const { return blocks_; }
  Block block(int b) const;
  std::size_t index(int iqx, int iqy) const;
  // A multiplier (one real per mode) in Fourier's layout of a serial transform (ny rows of
  // nq modes), written in this layout (spectrum_size() reals; the unused ones left as
  // they are).
  void reorder(const double* rows, double* blocks) const;

  template <class Acc, class Pass>
  Acc forward_rows(const double* f, Complex* s, Pass&& pass);
  // The same with the row made by the pass: pass(j, row, acc) writes row j's nx values
  // into `row`, a buffer of the thread's (e.g. a field that is zero off a sparse set,
  // whose zeros then need not be read from memory).
  template <class Acc, class Pass>
  Acc forward_rows_from(Complex* s, Pass&& pass);
  template <class Acc, class Pass>
  Acc columns(Complex* s, int what, Pass&& pass, Complex* inverse_of = nullptr);
  template <class Acc, class Pass>
  Acc inverse_rows(const Complex* s, double* f, Pass&& pass);
  // The same without a destination: row j's c2r goes into a row buffer of the thread's,
  // handed to pass(j, row, acc), which makes what it needs of it (e.g. f = h + row).
  template <class Acc, class Pass>
  Acc inverse_rows_through(const Complex* s, Pass&& pass);

  // A forward and an inverse transform with nothing fused in: y = inverse(forward(x)), s
  // the spectrum between them (the unit the fused sweeps' cost is measured in).
  void pair(const double* x, Complex* s, double* y) {
    forward_rows<None>(x, s, [](std::size_t, None&) {});
    columns<None>(s, kForward | kInverse, [](const Block&, None&) {});
    inverse_rows<None>(s, y, [](std::size_t, None&) {});
  }

  // Transforms done (a forward one counts with its column sweep, an inverse one too), and
  // the seconds of all sweeps, passes inside them included.
  long forward_count() const { return n_forward_; }
  long inverse_count() const { return n_inverse_; }
  double seconds() const { return seconds_; }
  // Where its plans came from (detail::plan_under_policy's words): "built-in wisdom", or
  // "rows: built-in wisdom, column blocks: estimate" where the two differ (a grid the
  // build did not plan, e.g. 8192² in the default build, still finds its rows there).
  const std::string& plan_source() const { return plan_source_; }

  // The partial result of a sweep without one.
  struct None {
    void merge(const None&) {}
  };

 private:
  // Row transforms into (from) row g of the thread's group of rows of modes; scatter and
  // gather move a group's modes to (from) the blocks.
  void row_forward(int thread, const double* row, int g);
  void row_inverse(int thread, int g, double* row);
  void column_transforms(Complex* s, int b, bool forward);
  double* row_buffer(int thread);  // nx aligned reals of the thread's
  void scatter(int thread, Complex* s, int j, int count) const;
  void gather(int thread, const Complex* s, int j, int count) const;
  std::size_t work() const { return std::size_t(nx_) * std::size_t(ny_); }
  // group(thread, j, j_end, acc) for the groups of up to kWidth rows [j, j_end) of each
  // thread's contiguous range of rows, partial results merged in thread order.
  template <class Acc, class Group>
  Acc row_groups(Group&& group);
  static int thread_id();


  int nx_, ny_, nq_, blocks_;
  std::size_t ldq_ = 0;  // modes per row of a thread's group (nq padded)
  std::size_t ld_ = 0;   // a block's column stride: ny + kColumnPad
  struct Plans;
  std::unique_ptr<Plans> plans_;
  long n_forward_ = 0, n_inverse_ = 0;
  double seconds_ = 0.0;
  std::string plan_source_;
};

template <class Acc, class Group>
Acc RowColumnFourier::row_groups(Group&& group) {
  const detail::ScopeTimer timer(seconds_);
  return Grid::parallel_reduce<Acc>(
      std::size_t(ny_),
      [&](std::size_t j0, std::size_t j1, Acc& acc) {
        const int t = thread_id();
        Acc local;
        for (std::size_t j = j0; j < j1; j += kWidth) group(t, j, std::min(j1, j + kWidth), local);
        acc.merge(local);
      },
      work());
}

template <class Acc, class Pass>
Acc RowColumnFourier::forward_rows(const double* f, Complex* s, Pass&& pass) {
  const std::size_t nx = std::size_t(nx_);
  return row_groups<Acc>([&](int t, std::size_t j, std::size_t g1, Acc& local) {
    for (std::size_t i = j; i < g1; ++i) {
      pass(i, local);
      row_forward(t, f + i * nx, int(i - j));
    }
    scatter(t, s, int(j), int(g1 - j));
  });
}

template <class Acc, class Pass>
Acc RowColumnFourier::forward_rows_from(Complex* s, Pass&& pass) {
  return row_groups<Acc>([&](int t, std::size_t j, std::size_t g1, Acc& local) {
    double* row = row_buffer(t);
    for (std::size_t i = j; i < g1; ++i) {
      pass(i, row, local);
      row_forward(t, row, int(i - j));
    }
    scatter(t, s, int(j), int(g1 - j));
  });
}

template <class Acc, class Pass>
Acc RowColumnFourier::columns(Complex* s, int what, Pass&& pass, Complex* inverse_of) {
  Complex* si = inverse_of ? inverse_of : s;
  const detail::ScopeTimer timer(seconds_);
  const Acc acc = Grid::parallel_reduce<Acc>(
      std::size_t(blocks_),
      [&](std::size_t b0, std::size_t b1, Acc& part) {
        Acc local;
        for (std::size_t b = b0; b < b1; ++b) {
          if (what & kForward) column_transforms(s, int(b), true);
          pass(block(int(b)), local);
          if (what & kInverse) column_transforms(si, int(b), false);
        }
        part.merge(local);
      },
      work());
  if (what & kForward) ++n_forward_;
  if (what & kInverse) ++n_inverse_;
  return acc;
}

template <class Acc, class Pass>
Acc RowColumnFourier::inverse_rows(const Complex* s, double* f, Pass&& pass) {
  const std::size_t nx = std::size_t(nx_);
  return row_groups<Acc>([&](int t, std::size_t j, std::size_t g1, Acc& local) {
    gather(t, s, int(j), int(g1 - j));
    for (std::size_t i = j; i < g1; ++i) {
      row_inverse(t, int(i - j), f + i * nx);
      pass(i, local);
    }
  });
}

template <class Acc, class Pass>
Acc RowColumnFourier::inverse_rows_through(const Complex* s, Pass&& pass) {
  return row_groups<Acc>([&](int t, std::size_t j, std::size_t g1, Acc& local) {
    gather(t, s, int(j), int(g1 - j));
    double* row = row_buffer(t);
    for (std::size_t i = j; i < g1; ++i) {
      row_inverse(t, int(i - j), row);
      pass(i, static_cast<const double*>(row), local);
    }
  });
}

}  // namespace cmc
