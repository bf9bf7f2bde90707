// Writes a run's results: DIR/summary.json (the readable record; names are stable,
// later tooling reads them), DIR/result.h5 (the fields of every step, with units as
// attributes, for h5py) and DIR/result.xdmf (a pointer file so ParaView can open the
// HDF5 fields). Everything is written under a temporary name and renamed into place
// only when complete, so an interrupted run never leaves a half-written result.
#pragma once

#include "cmc/run/Driver.hpp"

#include <filesystem>
#include <string>

#include <toml++/toml.h>

namespace cmc {

// What an interrupted run left behind: the finished steps and the last solved state.
struct ResumePoint {
  std::vector<StepRecord> done;
  ContactState state;
};

class Writer {
 public:
  // With `resume`, a partial run of the same case in `dir` is continued (see
  // resume_point()); without, any partial run there is discarded.
  Writer(std::filesystem::path dir, const Case& c, const Scene& s, bool resume = false);
  ~Writer();  // keeps the partial files of an unfinished run, so it can be resumed
  // The steps a resumed run can skip and its warm start (empty without --resume).
  const ResumePoint& resume_point() const { return resume_; }
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  // Append one solved step's fields (only when the case asks for fields).
  void add_step(const StepRecord& rec, const ContactState& st);
  // Write summary.json (+ result.h5, result.xdmf when fields were written) and move
  // them into place. `extra` entries are merged into the summary's top level.
  void finish(const RunSummary& run, const toml::table& extra = {});
  // A run that failed: summary.json with status "failed" and the message, no fields.
  void fail(const std::string& message);

  static toml::table step_json(const StepRecord& r);
  const std::filesystem::path& dir() const { return dir_; }

 private:
  toml::table summary_base() const;
  void load_partial();
  std::filesystem::path dir_, h5_tmp_, progress_, checkpoint_;
  ResumePoint resume_;
  toml::array records_;
  const Case& case_;
  const Scene& scene_;
  long long file_ = -1;  // hid_t
  int steps_written_ = 0;
};

// Write `text` to `path` atomically (temporary file in the same folder, then rename).
void write_atomically(const std::filesystem::path& path, const std::string& text);
std::string to_json(const toml::table& t);

}  // namespace cmc
