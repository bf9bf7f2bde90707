// Where cmc finds the files it ships: the case files (cases/, bases included), the stored
// reference curves (reference/) and the overlay script of `cmc check` (reports/plot_check.py).
//
// A data folder is one that holds both cases/ and reference/. The places looked, in order:
//   1. $CMC_DATA_DIR, where set;
//   2. beside the code that is running, found from the file it was loaded from (the `cmc`
//      program, or the Python module cmc._core): that file's folder and up to four folders
//      above it, each as FOLDER/share/cmc (an install: PREFIX/bin/cmc finds PREFIX/share/cmc,
//      PREFIX/lib/python3.X/.../cmc/_core.so too; pip's package holds cmc/share/cmc) and as
//      FOLDER itself (a source checkout: build/cmc finds the checkout above build/);
//   3. the install prefix this build was configured with (CMAKE_INSTALL_PREFIX/share/cmc:
//      a program of another project linking the installed library), then the source
//      checkout it was configured from (a build folder outside the checkout).
// The places of 2 come first, so an installed tree can be moved as a whole.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace cmc::data {

// The places looked, in the order above (each once; they need not exist).
std::vector<std::filesystem::path> places();

// The first place that is a data folder; empty when none is.
std::filesystem::path root();

// The places looked, as one line for messages: "looked in A, B, C".
std::string places_text();

// A file the user named: `path` itself when it exists; else, for a relative path, the same
// path under the data folder (root()/path) when that exists, so that
// `cmc run cases/challenge/reference-load.toml` runs from any folder once cmc is installed;
// else `path` unchanged (its reader then says it is missing).
std::filesystem::path find(const std::filesystem::path& path);

}  // namespace cmc::data
