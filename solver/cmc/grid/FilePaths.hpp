// The files cmc reads and writes, as paths: what a path must be before it is read or
// written, and the one way every output file is written.
//
// Output files (every writer: run folders, `cmc surface --write`, `cmc reference --out`,
// `cmc check --out`, `cmc refine`, `cmc validate`): a target is either a path that does
// not exist yet or a regular file, which is replaced atomically (a temporary file beside
// it, renamed over it once complete; removed again whatever goes wrong). Anything else is
// refused before anything is written (OutputPathError, exit code 2): a folder, a device,
// a FIFO, a socket, and a symbolic link. cmc neither replaces a link nor writes through
// it; the message names what the link points to, which can be given instead. Links among
// the folders above the file are followed as usual.
//
// Here, in grid/ (the folder every other one may include), so that the surface writers,
// the run's writer, the reference curves and the commands share it.
#pragma once

#include <filesystem>
#include <functional>
#include <stdexcept>
#include <string>

namespace cmc {

// An output path cmc will not write: bad input (`cmc` exits with code 2).
struct OutputPathError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Throws OutputPathError unless `path` does not exist or is a regular file.
void check_output_file(const std::filesystem::path& path);

// A folder outputs go into: one that does not exist yet (the caller makes it) or a folder
// (a link to one is followed). The root folder is refused: nothing cmc writes belongs
// there. Throws OutputPathError naming the path.
void check_output_folder(const std::filesystem::path& dir);

// Writes `path` atomically: fill(tmp) writes the temporary file ".<name>.tmp<pid>" in the
// same folder, which is then renamed over `path` (checked before fill and again before the
// rename). Whatever fill or the rename throws, the temporary file is removed first.
void write_output_file(const std::filesystem::path& path, const std::function<void(const std::filesystem::path&)>& fill);
void write_output_text(const std::filesystem::path& path, const std::string& text);

// Removes an earlier output of cmc's at `path` (nothing when absent); refuses, like
// check_output_file, anything but a regular file.
void remove_output_file(const std::filesystem::path& path);

// Why `path` cannot be read as an input file (empty: it can): "no such file", "is a
// folder", "is a symbolic link that cannot be resolved (a loop, or a missing target)",
// "is not a regular file (a pipe, terminal or device)".
std::string input_file_problem(const std::filesystem::path& path);

}  // namespace cmc
