// cmc sweep: one case run once per point of a product of --over values and --grids, each
// point into its own folder (cmd_sweep.cpp; the points and folders: sweep_plan.cpp; the
// table of results: sweep_table.cpp).
#pragma once

#include "cmc/input/Case.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <toml++/toml.h>

namespace cmc::app {

// One --over KEY=V1,V2,...: a case key and its values, each as written (TOML text).
struct SweepAxis {
  std::string key;
  std::vector<std::string> values;
};

// "KEY=V1,V2,..." split at the commas outside brackets, braces and quotes (a value may be
// an array: loading.values=[1e5,2e5],[3e5]). CaseError naming the argument when the key
// has no section, or the list or one of its values is empty, or a value comes twice.
SweepAxis parse_over(const std::string& argument);

// One run of the sweep.
struct SweepPoint {
  std::vector<std::pair<std::string, std::string>> values;  // (key, value text) per axis
  int grid = 0;                                              // the --grids size; 0: the case's
  std::vector<std::string> sets;  // every --set of its run: the command's, then key=value, grid.n=N
  std::string folder;             // relative to the sweep's folder
  std::string label() const;      // "interaction.tabor=0.1, n = 64" (for messages)
};

// Every point: the product of the axes' values (the first axis outermost) and the grids
// (innermost), in that order; `sets` the command's own --set assignments. Folders are
// left empty: sweep_folders fills them once the points' cases are read.
std::vector<SweepPoint> sweep_points(const std::vector<SweepAxis>& axes, const std::vector<int>& grids,
                                     const std::vector<std::string>& sets);

// The default folder pattern: "KEY_{KEY}" per axis, nested, then "n{n}" when --grids is
// given (no axes: "n{n}").
std::string default_folder_pattern(const std::vector<SweepAxis>& axes, bool grids);

// Each point's folder from `pattern`: {KEY} is the point's value of the swept KEY as a
// folder name (folder_text), {n} its grid's points per side (`cases[i].grid.nx`). CaseError
// naming --folder for an unknown or unclosed placeholder, a path that is absolute or has
// an empty, "." or ".." part, or two points sharing a folder.
void sweep_folders(std::vector<SweepPoint>& points, const std::vector<Case>& cases, const std::string& pattern);

// A value as part of a folder name: a quoted string without its quotes; any character
// but letters, digits and . _ + - as '_' ("[1e5, 2e5]" -> "_1e5__2e5_").
std::string folder_text(const std::string& value);

// What a point's run ended with, read back from its summary.json (absent: not run).
struct PointResult {
  std::string status = "not_run";  // converged, not_converged, failed, not_run
  std::string how;                 // ran, resumed, done earlier, kept, "" (not run)
  std::string message;
  long long nx = 0, ny = 0, iterations = 0;
  double wall_s = 0.0;  // the steps' solve time, over every process that worked on them
  // The last step's (absent where the run wrote none: a failed run, observables off).
  std::optional<double> contact_fraction, repulsive_fraction, mean_gap_m, mean_pressure_pa;
};

// The result recorded in `summary` (a summary.json read with read_json_file).
PointResult point_result(const toml::table& summary, const std::string& how);

// OUT/sweep.json and OUT/sweep.md: one record / row per point (sweep_table.cpp).
struct SweepTable {
  std::string case_file, pattern;
  std::vector<SweepAxis> axes;
  std::vector<int> grids;
  std::vector<std::string> sets;
};
std::string sweep_json(const SweepTable& t, const std::vector<SweepPoint>& points, const std::vector<PointResult>& results);
std::string sweep_markdown(const SweepTable& t, const std::vector<SweepPoint>& points,
                           const std::vector<PointResult>& results);

}  // namespace cmc::app
