// The ranks of a distributed run: which process this is, how a grid is split among
// them, and the few collective operations above the reductions (Grid.hpp) that cmc
// needs: a halo row, gathering rows or a column, broadcasting a text.
//
// Built with -DCMC_MPI=ON (Open MPI and FFTW's MPI interface from Debian) and started
// with mpirun, cmc splits every grid into slabs of rows along y, exactly as FFTW's MPI
// interface splits its r2c transforms (fftw_mpi_local_size_2d: blocks of ceil(ny/np)
// rows; the r2c spectrum is split along qy into the same rows). Without MPI, or with
// one rank, every function here is the identity or a copy and nothing is split.
//
// What runs where: the scene's surface is made whole on every rank and then cut into
// slabs (the same heights, bit for bit, as a serial run; the whole map is held during
// setup only); solvers, observables and reductions work on slabs; rank 0 alone writes
// files and prints.
#pragma once

#include "cmc/grid/Grid.hpp"

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace cmc {

// MPI for the lifetime of the program (main() holds one): initialises MPI (and FFTW's
// MPI interface) in the MPI build, nothing otherwise.
class RankSession {
 public:
  RankSession(int& argc, char**& argv);
  ~RankSession();
  RankSession(const RankSession&) = delete;
  RankSession& operator=(const RankSession&) = delete;
};

int rank();         // 0 .. ranks() - 1
int ranks();        // 1 without MPI
bool is_root();     // rank() == 0: the rank that writes files and prints
// Ranks that mpirun started on this machine (Open MPI's OMPI_COMM_WORLD_LOCAL_SIZE; 1
// without): they share its cores and its memory.
int ranks_on_this_machine();

// Inside this scope reductions stay on this rank: for data that every rank holds whole
// (the scene's surface before it is cut into slabs, per-patch lists). Nestable.
class LocalReductions {
 public:
  LocalReductions();
  ~LocalReductions();
  LocalReductions(const LocalReductions&) = delete;
  LocalReductions& operator=(const LocalReductions&) = delete;
};

// This rank's slab of the whole grid g (g itself with one rank). Throws
// std::invalid_argument, saying what to change, for a grid that cannot be split:
// a 1-D line (ny == 1), or fewer rows than ranks need.
Grid distribute(const Grid& g);
// The rows of a whole-grid field that this rank's slab holds.
Field slab_of(const Grid& slab, const Field& whole);

// The row above this slab's last row (global row (y0 + rows()) mod ny, periodic), and
// the row below its first: from the neighbouring rank (or this one). nx entries each.
// V: Mask (bytes) or Field.
template <class V>
V row_above(const Grid& g, const V& f);
template <class V>
V row_below(const Grid& g, const V& f);

// Rank r's `local` vectors, in rank order, on every rank.
std::vector<std::vector<double>> allgather(const std::vector<double>& local);
std::vector<std::vector<std::int64_t>> allgather(const std::vector<std::int64_t>& local);
// Rank 0's text on every rank.
void broadcast(std::string& text);
// Whether any rank says `flag` (the same answer on every rank).
bool any_rank(bool flag);
// Ends every rank now with exit code `code` (MPI_Abort); returns only without MPI.
void abort_all_ranks(int code);

// Moves the first `rows` rows of a grid between two splits of them among the ranks: from
// slabs of grid `from` (rows of from.nx values) into slabs of grid `to` (rows of to.nx >=
// from.nx values; the row's first from.nx entries), and back. The free boundary's
// zero-padded transform grid (2ny rows split by FFTW) and its contact grid (ny rows split
// alike) hold the contact rows on different ranks: this is the all-to-all between them.
// Without MPI, or with one rank, a strided copy.
class RowExchange {
 public:
  RowExchange(const Grid& from, const Grid& to, int rows);
  // to_field (to.size()) rows [0, rows) <- from_field (from.size()); the rest of to_field untouched.
  void forward(const double* from_field, double* to_field) const;
  // from_field <- to_field's rows [0, rows), first from.nx entries of each.
  void backward(const double* to_field, double* from_field) const;

 private:
  int nx_from_, nx_to_;
  int my_from0_, my_from_rows_, my_to0_, my_to_rows_;  // this rank's rows of each split, within [0, rows)
  std::vector<int> send_counts_, send_displs_, recv_counts_, recv_displs_;  // in doubles (forward)
  mutable std::vector<double> send_, recv_;
};

// Every row of a field, on rank 0, in blocks of rows: visit(y0, rows, values) is called
// on rank 0 for blocks of about 4 MiB in the order of the rows (rank 0's own first, then
// each rank's in rank order); other ranks send theirs. Rank 0 holds one block of another
// rank at a time. Without MPI: the blocks of this field.
void for_each_slab(const Grid& g, const double* local, const std::function<void(int, int, const double*)>& visit);
// The inverse: rank 0 fills the blocks of every rank's rows with fill(y0, rows, values),
// in the same order, and sends them; every rank receives its own into `local`.
void scatter_slabs(const Grid& g, double* local, const std::function<void(int, int, double*)>& fill);

}  // namespace cmc
