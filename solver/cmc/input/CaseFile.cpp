// Reading a case file: the TOML on disk, the --set overrides, then the parser (Case.hpp).
#include "cmc/input/Case.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

namespace cmc {

Case load_case(const std::string& path, const std::vector<std::string>& overrides) {
  // A case file is a regular file of bounded size: a folder or a pipe would otherwise
  // read as an empty case ("missing required section [case]"), and its folder anchors
  // the relative paths in it.
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) throw CaseError(path + ": cannot open the case file: no such file");
  if (fs::is_directory(st)) throw CaseError(path + ": is a folder, expected a case file (TOML)");
  if (!fs::is_regular_file(st))
    throw CaseError(path + ": is not a regular file (a pipe, terminal or device), expected a case file (TOML) on disk");
  if (const auto size = fs::file_size(path, ec); !ec && size > CaseLimits::kMaxCaseFileBytes)
    throw CaseError(path + ": is " + memory_text(double(size)) + ", expected a case file (TOML) of at most " +
                    memory_text(double(CaseLimits::kMaxCaseFileBytes)));
  std::ifstream in(path);
  if (!in) throw CaseError(path + ": cannot open the case file (not readable)");
  toml::table t;
  try {
    t = toml::parse(in, path);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << path << ": not valid TOML at line " << e.source().begin.line << ", column " << e.source().begin.column
      << ": " << e.description();
    throw CaseError(s.str());
  }
  for (const auto& o : overrides) apply_override(t, o);
  return parse_case(t, path);
}

}  // namespace cmc
