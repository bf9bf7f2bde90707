#include "cmc/grid/RowColumnFourier.hpp"

#include "cmc/grid/ColumnBlockPlans.hpp"

#include <fftw3.h>
#include <omp.h>

#include <algorithm>
#include <cstdint>
#if defined(__SSE2__)
#include <emmintrin.h>
#include <xmmintrin.h>
#endif
#include <stdexcept>

namespace cmc {

static_assert(RowColumnFourier::kWidth == detail::kColumnBlock);

// The row plans are FFTW's 1-D r2c and c2r of length nx (out of place, aligned), the same
// transforms a 1-D Fourier plans; the column plans those of ColumnBlockPlans.hpp. One set
// serves every thread (FFTW's new-array execute functions are thread safe); each thread
// has a row of reals and a row of modes of its own.
struct RowColumnFourier::Plans {
  FftwPlan row_r2c, row_c2r;
  FftwPlan col_forward, col_inverse;            // blocks of kColumnBlock columns
  FftwPlan last_forward, last_inverse;          // the last block (its own width)
  std::vector<Field> real_rows;                 // one per thread
  std::vector<Spectrum> mode_rows;              // kWidth rows per thread
};

RowColumnFourier::RowColumnFourier(int nx, int ny) : nx_(nx), ny_(ny), nq_(nx / 2 + 1) {
  if (nx <= 0 || ny <= 1) throw std::invalid_argument("RowColumnFourier: needs a two-dimensional grid");
  blocks_ = (nq_ + detail::kColumnBlock - 1) / detail::kColumnBlock;
  ld_ = std::size_t(ny) + std::size_t(detail::kColumnPad);
  plans_ = std::make_unique<Plans>();
  Plans& P = *plans_;
  const int threads = std::max(1, thread_count());
  P.real_rows.assign(std::size_t(threads), Field(std::size_t(nx)));
  // A group of kWidth rows of modes per thread, each row padded to a multiple of 4 modes
  // (64 bytes) so that every row has the planning row's alignment.
  ldq_ = (std::size_t(nq_) + 3) / 4 * 4;
  P.mode_rows.assign(std::size_t(threads), Spectrum(std::size_t(kWidth) * ldq_));
  Spectrum scratch(std::size_t(detail::kColumnBlock) * ld_);
  auto* r = P.real_rows[0].data();
  auto* c = reinterpret_cast<fftw_complex*>(P.mode_rows[0].data());
  auto* blk = reinterpret_cast<fftw_complex*>(scratch.data());
  const int full = std::min(nq_, int(detail::kColumnBlock)), last = block(blocks_ - 1).width;
  // Rows and columns planned apart: a grid the build did not plan (e.g. 8192² in the default
  // build) still gets its rows, 1-D lines up to 65536, from the built-in wisdom.
  const char* rows = detail::plan_under_policy(1, [&](unsigned flags) {
    P.row_r2c.reset(fftw_plan_dft_r2c_1d(nx, r, c, flags));
    P.row_c2r.reset(fftw_plan_dft_c2r_1d(nx, c, r, flags));
    return P.row_r2c && P.row_c2r;
  });
  const char* columns = detail::plan_under_policy(1, [&](unsigned flags) {
    P.col_forward.reset(detail::plan_column_block(ny, full, blk, FFTW_FORWARD, flags));
    P.col_inverse.reset(detail::plan_column_block(ny, full, blk, FFTW_BACKWARD, flags));
    P.last_forward.reset(detail::plan_column_block(ny, last, blk, FFTW_FORWARD, flags));
    P.last_inverse.reset(detail::plan_column_block(ny, last, blk, FFTW_BACKWARD, flags));
    return P.col_forward && P.col_inverse && P.last_forward && P.last_inverse;
  });
  plan_source_ = std::string(rows) == columns ? std::string(rows)
                                              : std::string("rows: ") + rows + ", column blocks: " + columns;
  save_fftw_wisdom();
}

RowColumnFourier::~RowColumnFourier() = default;

RowColumnFourier::Block RowColumnFourier::block(int b) const {
  const int iqx0 = b * detail::kColumnBlock;
  const int width = std::min(int(detail::kColumnBlock), nq_ - iqx0);
  const std::size_t begin = std::size_t(iqx0) * ld_;
  return {begin, begin + std::size_t(width) * ld_, ld_, iqx0, width, ny_};
}

std::size_t RowColumnFourier::index(int iqx, int iqy) const {
  const Block B = block(iqx / detail::kColumnBlock);
  return B.begin + std::size_t(iqx - B.iqx0) * ld_ + std::size_t(iqy);
}

void RowColumnFourier::reorder(const double* rows, double* blocks) const {
  for (int b = 0; b < blocks_; ++b) {
    const Block B = block(b);
    for (int c = 0; c < B.width; ++c)
      for (int j = 0; j < ny_; ++j)
        blocks[B.begin + std::size_t(c) * ld_ + std::size_t(j)] =
            rows[std::size_t(j) * std::size_t(nq_) + std::size_t(B.iqx0 + c)];
  }
}

double* RowColumnFourier::row_buffer(int thread) { return plans_->real_rows[std::size_t(thread)].data(); }

int RowColumnFourier::thread_id() { return omp_get_thread_num(); }

// A row that does not share the planning arrays' alignment (nx not a multiple of the SIMD
// width) goes through the thread's aligned row: FFTW's new-array functions need it.
void RowColumnFourier::row_forward(int thread, const double* row, int g) {
  Plans& P = *plans_;
  double* r = const_cast<double*>(row);
  if (fftw_alignment_of(r) != fftw_alignment_of(P.real_rows[0].data())) {
    r = P.real_rows[std::size_t(thread)].data();
    std::copy_n(row, nx_, r);
  }
  Complex* c = P.mode_rows[std::size_t(thread)].data() + std::size_t(g) * ldq_;
  fftw_execute_dft_r2c(static_cast<fftw_plan>(P.row_r2c.get()), r, reinterpret_cast<fftw_complex*>(c));
}

void RowColumnFourier::row_inverse(int thread, int g, double* row) {
  Plans& P = *plans_;
  Complex* c = P.mode_rows[std::size_t(thread)].data() + std::size_t(g) * ldq_;
  const bool aligned = fftw_alignment_of(row) == fftw_alignment_of(P.real_rows[0].data());
  double* r = aligned ? row : P.real_rows[std::size_t(thread)].data();
  fftw_execute_dft_c2r(static_cast<fftw_plan>(P.row_c2r.get()), reinterpret_cast<fftw_complex*>(c), r);
  if (!aligned) std::copy_n(r, nx_, row);
}

// The modes of rows [j, j + count) (count <= kWidth), held in the thread's group of rows,
// to (from) their blocks: each column of a block takes count contiguous modes of the
// group, 128 bytes (two cache lines) for a full group, so a group writes (reads) whole
// lines; the transposition of the group's count x width tile happens in the cache.
//
// scatter writes with streaming (non-temporal) stores where it can (SSE2, one mode a
// store): the spectrum is written whole before the column sweep reads any of it, and at
// 2048² and above it does not fit in the caches, so an ordinary store first reads the line
// it overwrites (a third more traffic) and then evicts what the sweep is working on. perf
// on the challenge at 2048² (adhesion, 2 threads) had scatter and gather at 7.2 % and
// 6.8 % of the solve, their stores copying one double at a time. A copy: the same bits.
void RowColumnFourier::scatter(int thread, Complex* s, int j, int count) const {
  const Complex* rows = plans_->mode_rows[std::size_t(thread)].data();
  const std::size_t ld = ld_;
  for (int b = 0; b < blocks_; ++b) {
    const Block B = block(b);
    for (int c = 0; c < B.width; ++c) {
      const Complex* src = rows + std::size_t(B.iqx0 + c);
      Complex* dst = s + B.begin + std::size_t(c) * ld + std::size_t(j);
#if defined(__SSE2__)
      double* d = reinterpret_cast<double*>(dst);
      if ((reinterpret_cast<std::uintptr_t>(d) & 15u) == 0) {
        for (int r = 0; r < count; ++r)
          _mm_stream_pd(d + 2 * r, _mm_loadu_pd(reinterpret_cast<const double*>(src + std::size_t(r) * ldq_)));
        continue;
      }
#endif
      for (int r = 0; r < count; ++r) dst[r] = src[std::size_t(r) * ldq_];
    }
  }
#if defined(__SSE2__)
  _mm_sfence();  // the streamed stores are seen before the sweep's end hands s on
#endif
}
void RowColumnFourier::gather(int thread, const Complex* s, int j, int count) const {
  Complex* rows = plans_->mode_rows[std::size_t(thread)].data();
  const std::size_t ld = ld_;
  for (int b = 0; b < blocks_; ++b) {
    const Block B = block(b);
    const Complex* col = s + B.begin + std::size_t(j);
#if defined(__SSE2__)
    // The next group's modes of this block (the same number of rows, right after these in
    // each column): asked for now, so that they arrive while this group's rows are
    // transformed.
    if (j + 2 * count <= ny_) {
      const std::size_t bytes = std::size_t(count) * sizeof(Complex);
      for (int c = 0; c < B.width; ++c) {
        const char* next = reinterpret_cast<const char*>(col + std::size_t(c) * ld + std::size_t(count));
        for (std::size_t o = 0; o < bytes; o += 64) _mm_prefetch(next + o, _MM_HINT_T1);
      }
    }
#endif
    for (int c = 0; c < B.width; ++c) {
      const Complex* src = col + std::size_t(c) * ld;
      Complex* dst = rows + std::size_t(B.iqx0 + c);
      for (int r = 0; r < count; ++r) dst[std::size_t(r) * ldq_] = src[r];
    }
  }
}

void RowColumnFourier::column_transforms(Complex* s, int b, bool forward) {
  const Plans& P = *plans_;
  const bool last = b == blocks_ - 1 && block(b).width != std::min(int(detail::kColumnBlock), nq_);
  const FftwPlan& plan = forward ? (last ? P.last_forward : P.col_forward) : (last ? P.last_inverse : P.col_inverse);
  auto* blk = reinterpret_cast<fftw_complex*>(s + block(b).begin);
  fftw_execute_dft(static_cast<fftw_plan>(plan.get()), blk, blk);
}

}  // namespace cmc
