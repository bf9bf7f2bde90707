// Writes a run's results: DIR/summary.json (the readable record; names are stable,
// later tooling reads them), DIR/result.h5 (the fields of every step, with units as
// attributes, for h5py) and DIR/result.xdmf (a pointer file so ParaView can open the
// HDF5 fields). They are written only when the run finishes, each under a temporary name
// renamed into place when complete, so an interrupted run never leaves a half-written
// result, nor an earlier run's (they are removed when a run starts).
//
// While a run is unfinished its folder holds:
//   DIR/INCOMPLETE               says so, and how to continue it (removed when it finishes);
//   DIR/.partial/step_NNNN.h5    each finished step's fields, written atomically;
//   DIR/.partial/checkpoint.h5   where the run stands (a RunPoint: the finished steps'
//                                records, the state to go on from and the load path's
//                                walk, or where a quasi-static step's solve stands inside
//                                it), replaced atomically at every checkpoint; --resume
//                                continues from it exactly as if the run had not stopped;
//   DIR/.cmc.lock                the lock of the process writing there (OutputLock.hpp).
//
// A run whose quasi-static solve stopped at its outer-step limit (solver.max_outer_steps)
// finishes like any other (summary.json with status "not_converged", result.h5), but keeps
// .partial/ with the last checkpoint from before that stop (checkpoints are not replaced
// after it: the later steps start from a state that is not the answer) and a file
// .partial/stopped.toml naming the limit. --resume with a larger limit continues that solve
// where the checkpoint stood, and gives the results a fresh run with the larger limit gives,
// bit for bit; --resume with the same limit leaves the folder as it is (RunStopped, exit 3)
// and with a smaller one is refused (exit 2). summary.json's
// "continue" says how. So a solve that creeps towards its tolerance for hours is not lost
// at its limit.
#pragma once

#include "cmc/grid/FilePaths.hpp"
#include "cmc/output/OutputLock.hpp"
#include "cmc/run/Driver.hpp"

#include <filesystem>
#include <stdexcept>
#include <string>

#include <toml++/toml.h>

namespace cmc {

// --resume of a run that stopped at its outer-step limit, with the same limit: the folder
// is left as it is (the run's status stays "not_converged"; `cmc run` exits 3).
struct RunStopped : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Writer {
 public:
  // Locks `dir` (OutputBusy when another process writes there). With `resume`, a partial
  // run of the same case in `dir` is continued (see resume_point()); without, or when
  // there is none, any partial run there is discarded. An earlier run's results are removed.
  Writer(std::filesystem::path dir, const Case& c, const Scene& s, bool resume = false);
  ~Writer();  // keeps the partial files of an unfinished run, so it can be resumed
  // Where the interrupted run stood (nothing done, and an empty state, without --resume).
  const RunPoint& resume_point() const { return resume_; }
  RunPoint& resume_point() { return resume_; }  // run_scene moves the fields out of it
  bool resuming() const { return resuming_; }
  // What the caller should tell the user about the folder (empty: nothing), e.g. that a
  // partial run of an earlier cmc version there could not be continued and was discarded.
  const std::string& notice() const { return notice_; }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  // Keep one solved step: its record, and its fields when the case asks for fields.
  void add_step(const StepRecord& rec, const ContactState& st);
  // Commit a point the run can be continued from: the steps added so far, the state the
  // run goes on from and its load path's walk (null: none), replacing the last checkpoint.
  // `inside`: where the next step's solve stands (its state is then not written).
  void checkpoint(const ContactState& st, const PathState* path, const OuterPoint* inside = nullptr);
  // Write summary.json (+ result.h5 when fields or observables were written, result.xdmf
  // when fields were) and move
  // them into place. `extra` entries are merged into the summary's top level.
  void finish(const RunSummary& run, const toml::table& extra = {});
  // A run that failed: summary.json with status "failed" and the message, no fields.
  void fail(const std::string& message);

  // Where the run's first solve started when not from scratch (a coarser run's state,
  // CoarseStart.hpp): written into summary.json as "start_from" and kept in checkpoints,
  // so a resumed run records it too. A resumed run keeps the record it was started with.
  void set_start(const toml::table& record) {
    if (start_.empty()) start_ = record;
  }
  const toml::table& start() const { return start_; }

  static toml::table step_json(const StepRecord& r);
  const std::filesystem::path& dir() const { return dir_; }

 private:
  toml::table summary_base() const;
  std::string fft_plans() const;  // where the transforms ran (summary.json grid.fft_plans)
  void load_partial();
  std::filesystem::path step_file(int index) const;
  // Whether the steps go into result.h5: with their fields, or with observables alone.
  bool writes_step_files() const { return case_.write_fields || case_.observables.enabled; }
  // Whether `rec` is a quasi-static solve stopped at the case's outer-step limit.
  bool stopped_at_limit(const StepRecord& rec) const;
  OutputLock lock_;
  std::filesystem::path dir_, partial_, checkpoint_, marker_;
  RunPoint resume_;
  bool resuming_ = false;
  int stopped_step_ = -1;  // the first step stopped at its outer-step limit (-1: none)
  std::string notice_;
  toml::array records_;
  toml::table start_;
  const Case& case_;
  const Scene& scene_;
};

// Output files are written with write_output_file / write_output_text (grid/FilePaths.hpp).
std::string to_json(const toml::table& t);

}  // namespace cmc
