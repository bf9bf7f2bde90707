// What a run's output folder may hold before cmc writes into it, and the files of a
// partial run in it (Writer.hpp describes the folder).
//
// Rules (cases/README.md, "Output folders"):
// - cmc replaces only its own results. A DIR/summary.json that is not a cmc summary (no
//   "cmc_version"), or a result.h5 / result.xdmf in a folder that holds no cmc run (no
//   cmc summary.json, no INCOMPLETE), is refused (exit 2) and left as it is.
// - Each of cmc's files must be a regular file (or absent): a folder, device, FIFO or link
//   of that name is refused (grid/FilePaths.hpp).
// - DIR/.partial/ is cmc's working folder: everything in it is cmc's, removed with it.
#pragma once

#include "cmc/input/Case.hpp"

#include <filesystem>
#include <string>

namespace cmc {

// Checks what an earlier run left in `dir` against the rules above; throws
// OutputPathError (exit 2) for anything cmc must not replace. clear_earlier_results also
// removes the earlier results (summary.json, result.h5, result.xdmf) and the temporary
// files of a process killed while writing them (".summary.json.tmpPID", in DIR and
// DIR/.partial/).
void check_earlier_results(const std::filesystem::path& dir);
void clear_earlier_results(const std::filesystem::path& dir);

// Why the results file of a finished step cannot be used to finish a resumed run (empty:
// it can): missing, not a readable HDF5 file (truncated, damaged), without the step's
// group `step_NNNN`, or, when the run writes `fields`, without them or with fields of
// another grid than the run's nx x ny.
std::string step_file_problem(const std::filesystem::path& file, int index, int nx, int ny, bool fields);

// The text of DIR/INCOMPLETE: what the folder holds and how to continue the run.
std::string incomplete_text(const Case& c, const std::filesystem::path& dir);

}  // namespace cmc
