#include "cmc/output/RunFolder.hpp"

#include "cmc/grid/FilePaths.hpp"
#include "cmc/surface/H5Handle.hpp"

#include <cstdio>
#include <fstream>
#include <regex>
#include <sstream>

namespace cmc {

namespace fs = std::filesystem;

namespace {
// Whether `file` is a summary.json that cmc wrote (every one names the cmc version).
bool cmc_summary(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str().find("\"cmc_version\"") != std::string::npos;
}
}  // namespace

void check_earlier_results(const fs::path& dir) {
  const fs::path summary = dir / "summary.json";
  std::error_code ec;
  for (const char* f : {"summary.json", "result.h5", "result.xdmf", "INCOMPLETE"}) check_output_file(dir / f);
  const bool has_summary = fs::exists(summary, ec);
  if (has_summary && !cmc_summary(summary))
    throw OutputPathError(summary.string() + ": is not a cmc run summary (it names no \"cmc_version\"); cmc replaces "
                          "only its own results: move it away or choose another --out");
  if (!has_summary && !fs::exists(dir / "INCOMPLETE", ec))
    for (const char* f : {"result.h5", "result.xdmf"})
      if (fs::exists(dir / f, ec))
        throw OutputPathError((dir / f).string() + ": the folder holds no cmc run (no summary.json, no INCOMPLETE) "
                              "that this file could belong to; cmc replaces only its own results: move it away or "
                              "choose another --out");
  const fs::file_status partial = fs::symlink_status(dir / ".partial", ec);
  if (partial.type() != fs::file_type::not_found && partial.type() != fs::file_type::directory)
    throw OutputPathError((dir / ".partial").string() + ": expected cmc's folder of a partial run (or nothing)");
}

void clear_earlier_results(const fs::path& dir) {
  check_earlier_results(dir);
  for (const char* f : {"summary.json", "result.h5", "result.xdmf"}) remove_output_file(dir / f);
  // Temporary files of a process killed while writing (".NAME.tmpPID", grid/FilePaths.hpp):
  // the folder is locked, so no other process is writing them now.
  static const std::regex temporary(R"(\.(summary\.json|result\.h5|result\.xdmf|INCOMPLETE|checkpoint\.h5|)"
                                    R"(step_[0-9]{4}\.h5|stopped\.toml)\.tmp[0-9]+)");
  std::error_code ec;
  for (const fs::path& folder : {dir, dir / ".partial"})
    for (const auto& e : fs::directory_iterator(folder, ec))
      if (e.is_regular_file(ec) && std::regex_match(e.path().filename().string(), temporary)) fs::remove(e.path(), ec);
}

namespace {
// The dimensions of a two-dimensional dataset, or {0, 0} for anything else.
std::pair<hsize_t, hsize_t> dataset_dims(hid_t file, const std::string& path) {
  H5Handle d(H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d.ok()) return {0, 0};
  H5Handle space(H5Dget_space(d), H5Sclose);
  hsize_t dims[2] = {0, 0};
  if (!space.ok() || H5Sget_simple_extent_ndims(space) != 2 || H5Sget_simple_extent_dims(space, dims, nullptr) != 2)
    return {0, 0};
  return {dims[0], dims[1]};
}
}  // namespace

std::string step_file_problem(const fs::path& file, int index, int nx, int ny, bool fields) {
  const std::string which = std::string(fields ? "the fields" : "the observables") + " of step " + std::to_string(index) + " (" + file.string() + ")";
  std::error_code ec;
  if (!fs::exists(file, ec)) return which + " are missing";
  H5Quiet quiet;
  H5Handle f(H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!f.ok()) return which + " are damaged: not a readable HDF5 file (truncated?)";
  char name[32];
  std::snprintf(name, sizeof name, "step_%04d", index);
  if (H5Lexists(f, name, H5P_DEFAULT) <= 0) return which + " are damaged: no " + name + " in it";
  if (!fields) return "";
  for (const std::string& path : {std::string(name) + "/pressure", std::string(name) + "/gap",
                                  std::string(name) + "/displacement"})
    if (H5Lexists(f, path.c_str(), H5P_DEFAULT) <= 0) return which + " are damaged: no " + path + " in it";
  for (const char* field : {"pressure", "gap", "displacement"}) {
    const auto [rows, columns] = dataset_dims(f, std::string(name) + "/" + field);
    if (rows != hsize_t(ny) || columns != hsize_t(nx))
      return which + " are not this run's: " + name + "/" + field + " is " + std::to_string(columns) + " x " +
             std::to_string(rows) + " points where the run has " + std::to_string(nx) + " x " + std::to_string(ny);
  }
  return "";
}

std::string incomplete_text(const Case& c, const fs::path& dir) {
  std::ostringstream m;
  m << "This folder holds an unfinished cmc run of case '" << c.name << "' (" << c.file
    << "): still running, interrupted or failed.\n"
    << "Its results (summary.json, result.h5, result.xdmf) are written only when it finishes.\n"
    << "To continue it from its last checkpoint (with the same --set options as the run that started it):\n"
    << "  cmc run " << c.file << " --out " << dir.string() << " --resume\n";
  return m.str();
}

}  // namespace cmc
