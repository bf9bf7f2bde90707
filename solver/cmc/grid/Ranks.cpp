#include "cmc/grid/Ranks.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#ifdef CMC_MPI
#include <fftw3-mpi.h>
#include <mpi.h>
#endif

namespace cmc {

namespace {
int local_depth = 0;  // LocalReductions scopes open
#ifdef CMC_MPI
bool mpi_started = false;
int node_ranks = 0;  // the ranks that share this node's memory (RankSession counts them)
#endif
}  // namespace

LocalReductions::LocalReductions() { ++local_depth; }
LocalReductions::~LocalReductions() { --local_depth; }

#ifdef CMC_MPI
RankSession::RankSession(int& argc, char**& argv) {
  int provided = 0;
  // Threads (OpenMP passes, FFTW's threads) never call MPI: FUNNELED is enough.
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  mpi_started = true;
  // The ranks on this node, whatever started them (mpirun, srun): counted once, here,
  // where every rank is (it is a collective call).
  MPI_Comm node;
  MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
  MPI_Comm_size(node, &node_ranks);
  MPI_Comm_free(&node);
}
RankSession::~RankSession() {
  if (!mpi_started) return;
  fftw_mpi_cleanup();
  MPI_Finalize();
  mpi_started = false;
}
int rank() {
  if (!mpi_started) return 0;
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}
int ranks() {
  if (!mpi_started) return 1;
  int n = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}
#else
RankSession::RankSession(int&, char**&) {}
RankSession::~RankSession() = default;
int rank() { return 0; }
int ranks() { return 1; }
#endif
bool is_root() { return rank() == 0; }
int ranks_on_this_machine() {
#ifdef CMC_MPI
  if (node_ranks > 0) return node_ranks;
#endif
  // Before MPI starts (thread_count() may ask early): what mpirun says.
  if (const char* s = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE")) return std::max(1, std::atoi(s));
  return 1;
}

namespace detail {
bool reductions_span_ranks() { return local_depth == 0 && ranks() > 1; }

std::vector<unsigned char> allgather_bytes(const void* bytes, std::size_t n) {
  std::vector<unsigned char> all(n * std::size_t(ranks()));
#ifdef CMC_MPI
  if (ranks() > 1) {
    MPI_Allgather(bytes, int(n), MPI_BYTE, all.data(), int(n), MPI_BYTE, MPI_COMM_WORLD);
    return all;
  }
#endif
  std::memcpy(all.data(), bytes, n);
  return all;
}

std::vector<std::vector<double>> allgather_doubles(const std::vector<double>& v) { return allgather(v); }
}  // namespace detail

std::size_t Grid::total(std::size_t n) {
  if (!detail::reductions_span_ranks()) return n;
  const auto all = detail::allgather_bytes(&n, sizeof n);
  std::size_t t = 0;
  for (std::size_t off = 0; off < all.size(); off += sizeof n) {
    std::size_t v;
    std::memcpy(&v, all.data() + off, sizeof v);
    t += v;
  }
  return t;
}

namespace {
// Rows of each rank as FFTW's MPI interface splits ny rows of an r2c transform.
struct Split {
  std::vector<int> y0, rows;
};
Split split_rows(const Grid& g) {
  Split s;
  const int np = ranks();
#ifdef CMC_MPI
  if (np > 1) {
    ptrdiff_t n0 = 0, start = 0;
    fftw_mpi_local_size_2d(g.ny, g.nx / 2 + 1, MPI_COMM_WORLD, &n0, &start);
    const long long mine[2] = {(long long)start, (long long)n0};
    std::vector<long long> all(2 * std::size_t(np));
    MPI_Allgather(mine, 2, MPI_LONG_LONG, all.data(), 2, MPI_LONG_LONG, MPI_COMM_WORLD);
    for (int r = 0; r < np; ++r) s.y0.push_back(int(all[2 * r])), s.rows.push_back(int(all[2 * r + 1]));
    return s;
  }
#endif
  (void)np;
  s.y0 = {0}, s.rows = {g.rows()};
  return s;
}
}  // namespace

Grid distribute(const Grid& g) {
  if (ranks() == 1) return g;
  if (g.ny < 2)
    throw std::invalid_argument("a one-dimensional grid (ny = 1) cannot be split among " + std::to_string(ranks()) +
                                " MPI ranks: run it with one rank");
  const Split s = split_rows(g);
  for (int r = 0; r < ranks(); ++r)
    if (s.rows[r] < 1)
      throw std::invalid_argument("the grid's " + std::to_string(g.ny) + " rows leave MPI rank " + std::to_string(r) +
                                  " with none: use at most " + std::to_string(ranks() - 1) + " ranks or a larger grid");
  Grid out = g;
  out.y0 = s.y0[rank()];
  out.local_ny = s.rows[rank()];
  return out;
}

Field slab_of(const Grid& slab, const Field& whole) {
  if (whole.size() != slab.points()) throw std::invalid_argument("slab_of: the field does not cover the whole grid");
  const auto b = whole.begin() + std::ptrdiff_t(std::size_t(slab.y0) * slab.nx);
  return Field(b, b + std::ptrdiff_t(slab.size()));
}

// ---------------------------------------------------------------- collectives

namespace {
// Rows in one block of for_each_slab / scatter_slabs: about 4 MiB of doubles, at least
// one row, so that writing a field costs 4 MiB of buffers, not a copy of it.
int rows_per_block(const Grid& g) {
  constexpr std::size_t kBlockBytes = std::size_t(4) << 20;
  return int(std::max<std::size_t>(1, kBlockBytes / (sizeof(double) * std::size_t(std::max(g.nx, 1)))));
}
}  // namespace

#ifdef CMC_MPI
namespace {
template <class T>
MPI_Datatype mpi_type();
template <>
MPI_Datatype mpi_type<double>() { return MPI_DOUBLE; }
template <>
MPI_Datatype mpi_type<std::int64_t>() { return MPI_INT64_T; }
template <>
MPI_Datatype mpi_type<std::uint8_t>() { return MPI_UINT8_T; }

template <class T>
std::vector<std::vector<T>> allgather_any(const std::vector<T>& local) {
  const int np = ranks();
  const int n = int(local.size());
  std::vector<int> counts(np), displs(np);
  MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD);
  int total = 0;
  for (int r = 0; r < np; ++r) displs[r] = total, total += counts[r];
  std::vector<T> flat(std::size_t(std::max(total, 1)));
  MPI_Allgatherv(local.data(), n, mpi_type<T>(), flat.data(), counts.data(), displs.data(), mpi_type<T>(),
                 MPI_COMM_WORLD);
  std::vector<std::vector<T>> out(np);
  for (int r = 0; r < np; ++r) out[r].assign(flat.begin() + displs[r], flat.begin() + displs[r] + counts[r]);
  return out;
}

// The row next to this slab: above its last row, or below its first.
template <class V>
V neighbour_row(const Grid& g, const V& f, bool above) {
  using T = typename V::value_type;
  const std::size_t nx = std::size_t(g.nx);
  V out(nx);
  if (!g.split() || ranks() == 1) {
    const int r = above ? (g.rows() % g.ny) : (g.ny - 1);
    std::copy_n(f.begin() + std::ptrdiff_t(std::size_t(r) * nx), nx, out.begin());
    return out;
  }
  const int np = ranks(), me = rank();
  const int up = (me + 1) % np, down = (me + np - 1) % np;
  // The row above my last is the next rank's first: each rank sends its first row down and
  // receives the next rank's. The row below my first is the previous rank's last.
  const int send_to = above ? down : up, recv_from = above ? up : down;
  const T* send = above ? f.data() : f.data() + std::size_t(g.rows() - 1) * nx;
  MPI_Sendrecv(send, int(nx), mpi_type<T>(), send_to, 11, out.data(), int(nx), mpi_type<T>(), recv_from, 11,
               MPI_COMM_WORLD, MPI_STATUS_IGNORE);
  return out;
}
}  // namespace

std::vector<std::vector<double>> allgather(const std::vector<double>& local) {
  if (ranks() == 1) return {local};
  return allgather_any(local);
}
std::vector<std::vector<std::int64_t>> allgather(const std::vector<std::int64_t>& local) {
  if (ranks() == 1) return {local};
  return allgather_any(local);
}
void broadcast(std::string& text) {
  if (ranks() == 1) return;
  long long n = (long long)text.size();
  MPI_Bcast(&n, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  text.resize(std::size_t(n));
  if (n) MPI_Bcast(text.data(), int(n), MPI_CHAR, 0, MPI_COMM_WORLD);
}
bool any_rank(bool flag) {
  if (ranks() == 1) return flag;
  int in = flag ? 1 : 0, out = 0;
  MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return out != 0;
}
void abort_all_ranks(int code) {
  std::fflush(stderr);
  if (ranks() > 1) MPI_Abort(MPI_COMM_WORLD, code);
}

void for_each_slab(const Grid& g, const double* local, const std::function<void(int, int, const double*)>& visit) {
  const int block = rows_per_block(g);
  if (ranks() == 1 || !g.split()) {
    if (is_root())
      for (int r = 0; r < g.rows(); r += block) visit(g.y0 + r, std::min(block, g.rows() - r), local + std::size_t(r) * g.nx);
    return;
  }
  const Split s = split_rows(g);
  if (!is_root()) {
    for (int r = 0; r < g.rows(); r += block)
      MPI_Send(local + std::size_t(r) * g.nx, int(std::size_t(std::min(block, g.rows() - r)) * g.nx), MPI_DOUBLE, 0, 21,
               MPI_COMM_WORLD);
    return;
  }
  for (int r = 0; r < g.rows(); r += block) visit(g.y0 + r, std::min(block, g.rows() - r), local + std::size_t(r) * g.nx);
  Field buf(std::size_t(block) * g.nx);
  for (int q = 1; q < ranks(); ++q)
    for (int r = 0; r < s.rows[q]; r += block) {
      const int n = std::min(block, s.rows[q] - r);
      MPI_Recv(buf.data(), int(std::size_t(n) * g.nx), MPI_DOUBLE, q, 21, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
      visit(s.y0[q] + r, n, buf.data());
    }
}

void scatter_slabs(const Grid& g, double* local, const std::function<void(int, int, double*)>& fill) {
  const int block = rows_per_block(g);
  if (ranks() == 1 || !g.split()) {
    if (is_root())
      for (int r = 0; r < g.rows(); r += block) fill(g.y0 + r, std::min(block, g.rows() - r), local + std::size_t(r) * g.nx);
    return;
  }
  const Split s = split_rows(g);
  if (!is_root()) {
    for (int r = 0; r < g.rows(); r += block)
      MPI_Recv(local + std::size_t(r) * g.nx, int(std::size_t(std::min(block, g.rows() - r)) * g.nx), MPI_DOUBLE, 0, 22,
               MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    return;
  }
  for (int r = 0; r < g.rows(); r += block) fill(g.y0 + r, std::min(block, g.rows() - r), local + std::size_t(r) * g.nx);
  Field buf(std::size_t(block) * g.nx);
  for (int q = 1; q < ranks(); ++q)
    for (int r = 0; r < s.rows[q]; r += block) {
      const int n = std::min(block, s.rows[q] - r);
      fill(s.y0[q] + r, n, buf.data());
      MPI_Send(buf.data(), int(std::size_t(n) * g.nx), MPI_DOUBLE, q, 22, MPI_COMM_WORLD);
    }
}
#else
namespace {
template <class V>
V neighbour_row(const Grid& g, const V& f, bool above) {
  const std::size_t nx = std::size_t(g.nx);
  const int r = above ? (g.rows() % g.ny) : (g.ny - 1);
  return V(f.begin() + std::ptrdiff_t(std::size_t(r) * nx), f.begin() + std::ptrdiff_t(std::size_t(r + 1) * nx));
}
}  // namespace
std::vector<std::vector<double>> allgather(const std::vector<double>& local) { return {local}; }
std::vector<std::vector<std::int64_t>> allgather(const std::vector<std::int64_t>& local) { return {local}; }
void broadcast(std::string&) {}
bool any_rank(bool flag) { return flag; }
void abort_all_ranks(int) {}
void for_each_slab(const Grid& g, const double* local, const std::function<void(int, int, const double*)>& visit) {
  const int block = rows_per_block(g);
  for (int r = 0; r < g.rows(); r += block) visit(g.y0 + r, std::min(block, g.rows() - r), local + std::size_t(r) * g.nx);
}
void scatter_slabs(const Grid& g, double* local, const std::function<void(int, int, double*)>& fill) {
  const int block = rows_per_block(g);
  for (int r = 0; r < g.rows(); r += block) fill(g.y0 + r, std::min(block, g.rows() - r), local + std::size_t(r) * g.nx);
}
#endif

// ---------------------------------------------------------------- row exchange

RowExchange::RowExchange(const Grid& from, const Grid& to, int rows) : nx_from_(from.nx), nx_to_(to.nx) {
  auto clip = [&](int y0, int n, int& a, int& m) {
    a = std::min(std::max(y0, 0), rows);
    m = std::max(0, std::min(y0 + n, rows) - a);
  };
  clip(from.y0, from.rows(), my_from0_, my_from_rows_);
  clip(to.y0, to.rows(), my_to0_, my_to_rows_);
#ifdef CMC_MPI
  if (ranks() > 1 && (from.split() || to.split())) {
    const Split sf = split_rows(from), st = split_rows(to);
    const int np = ranks();
    send_counts_.assign(np, 0), send_displs_.assign(np, 0), recv_counts_.assign(np, 0), recv_displs_.assign(np, 0);
    auto overlap = [&](int a0, int an, int b0, int bn) {
      const int lo = std::max({a0, b0, 0}), hi = std::min({a0 + an, b0 + bn, rows});
      return std::max(0, hi - lo);
    };
    int so = 0, ro = 0;
    for (int r = 0; r < np; ++r) {
      send_displs_[r] = so, recv_displs_[r] = ro;
      send_counts_[r] = overlap(from.y0, from.rows(), st.y0[r], st.rows[r]) * from.nx;
      recv_counts_[r] = overlap(sf.y0[r], sf.rows[r], to.y0, to.rows()) * from.nx;
      so += send_counts_[r], ro += recv_counts_[r];
    }
    send_.resize(std::size_t(so)), recv_.resize(std::size_t(ro));
  }
#endif
}

void RowExchange::forward(const double* from_field, double* to_field) const {
  const std::size_t nf = std::size_t(nx_from_), nt = std::size_t(nx_to_);
  if (send_counts_.empty()) {  // both splits are the same rows of one process
    for (int r = 0; r < my_from_rows_; ++r)
      std::copy_n(from_field + std::size_t(r) * nf, nf, to_field + std::size_t(my_from0_ - my_to0_ + r) * nt);
    return;
  }
#ifdef CMC_MPI
  // The rows this rank holds of [0, rows) are contiguous, and so are those it sends to
  // each rank (in rank order = row order): the send buffer is the rows themselves.
  std::copy_n(from_field, std::size_t(my_from_rows_) * nf, send_.data());
  MPI_Alltoallv(send_.data(), send_counts_.data(), send_displs_.data(), MPI_DOUBLE, recv_.data(), recv_counts_.data(),
                recv_displs_.data(), MPI_DOUBLE, MPI_COMM_WORLD);
  // Received in rank order, which is row order: rows my_to0_ .. my_to0_ + my_to_rows_ - 1.
  for (int r = 0; r < my_to_rows_; ++r) std::copy_n(recv_.data() + std::size_t(r) * nf, nf, to_field + std::size_t(r) * nt);
#endif
}

void RowExchange::backward(const double* to_field, double* from_field) const {
  const std::size_t nf = std::size_t(nx_from_), nt = std::size_t(nx_to_);
  if (send_counts_.empty()) {
    for (int r = 0; r < my_from_rows_; ++r)
      std::copy_n(to_field + std::size_t(my_from0_ - my_to0_ + r) * nt, nf, from_field + std::size_t(r) * nf);
    return;
  }
#ifdef CMC_MPI
  for (int r = 0; r < my_to_rows_; ++r) std::copy_n(to_field + std::size_t(r) * nt, nf, recv_.data() + std::size_t(r) * nf);
  MPI_Alltoallv(recv_.data(), recv_counts_.data(), recv_displs_.data(), MPI_DOUBLE, send_.data(), send_counts_.data(),
                send_displs_.data(), MPI_DOUBLE, MPI_COMM_WORLD);
  std::copy_n(send_.data(), std::size_t(my_from_rows_) * nf, from_field);
#endif
}

template <class V>
V row_above(const Grid& g, const V& f) {
  return neighbour_row(g, f, true);
}
template <class V>
V row_below(const Grid& g, const V& f) {
  return neighbour_row(g, f, false);
}
template std::vector<std::uint8_t> row_above(const Grid&, const std::vector<std::uint8_t>&);
template std::vector<std::uint8_t> row_below(const Grid&, const std::vector<std::uint8_t>&);
template Field row_above(const Grid&, const Field&);
template Field row_below(const Grid&, const Field&);

}  // namespace cmc
