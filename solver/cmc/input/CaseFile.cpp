// Reading a case file: the TOML on disk with the bases it names merged under it, the --set
// overrides, then the parser (Case.hpp).
//
// A base: a top-level `base = "path.toml"` (relative to the file that states it) names a
// case file whose keys the including file starts from; a relative base that is not there is
// looked for under cmc's data folder (input/DataDir.hpp), as is a case file named on the
// command line, so that a case of one's own can start from an installed one. Tables are merged key by key, the
// including file's keys replacing the base's; any other value (an array too) replaces the
// base's whole. A base may name a base of its own, at most CaseLimits::kMaxBaseDepth deep and
// never one already on the way (a cycle). A relative [surface] path stated in a base is read
// from the base's folder (it is rewritten relative to the including file). The resolved case
// (summary.json "case") is the merged table: it names no base.
#include "cmc/input/CaseSection.hpp"
#include "cmc/input/DataDir.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace cmc {

namespace {

namespace fs = std::filesystem;
using case_parsing::type_name;

// For a missing case file named `path` (relative to the folder it was looked for in first):
// where else it was looked for.
std::string also_looked(const fs::path& path) {
  if (path.is_absolute()) return "";
  const fs::path dir = data::root();
  return dir.empty() ? " (nor in cmc's data folder: " + data::places_text() + ")"
                     : " (nor " + (dir / path).string() + ")";
}

// The TOML of one case file, a regular file of bounded size: a folder or a pipe would
// otherwise read as an empty case ("missing required section [case]"), and its folder
// anchors the relative paths in it. Each message starts with `context` (for a base: the
// including file and its key) and the file's path; `also` says where else it was looked for.
toml::table read_toml_file(const std::string& path, const std::string& context, const std::string& also) {
  auto fail = [&](const std::string& what) { throw CaseError(context + path + ": " + what); };
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) fail("cannot open the case file: no such file" + also);
  if (fs::is_directory(st)) fail("is a folder, expected a case file (TOML)");
  if (!fs::is_regular_file(st)) fail("is not a regular file (a pipe, terminal or device), expected a case file (TOML) on disk");
  if (const auto size = fs::file_size(path, ec); !ec && size > CaseLimits::kMaxCaseFileBytes)
    fail("is " + memory_text(double(size)) + ", expected a case file (TOML) of at most " +
         memory_text(double(CaseLimits::kMaxCaseFileBytes)));
  std::ifstream in(path);
  if (!in) fail("cannot open the case file (not readable)");
  try {
    return toml::parse(in, path);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << "not valid TOML at line " << e.source().begin.line << ", column " << e.source().begin.column << ": "
      << e.description();
    fail(s.str());
  }
  return {};  // unreachable: fail() throws
}

std::string line_of(const toml::node& n) {
  return n.source().begin ? " (line " + std::to_string(n.source().begin.line) + ")" : "";
}

// A key as messages name it: "[grid]" for a section, "[grid] n" for a key in one.
std::string key_text(const std::string& section, const std::string& key, bool table) {
  if (section.empty()) return table ? "[" + key + "]" : key;
  return "[" + section + "] " + key;
}

// `over`'s keys moved onto `merged` (the base's): tables merged key by key, anything else
// replaced whole. A table on one side and a value on the other is an error naming both files.
void merge_over(toml::table& merged, toml::table& over, const std::string& over_file, const std::string& base_file,
                const std::string& section) {
  for (auto&& [k, v] : over) {
    const std::string key(k.str());
    toml::node* b = merged.get(key);
    if (b && b->is_table() != v.is_table())
      throw CaseError(over_file + ": " + key_text(section, key, true) + ": " + type_name(v) + " here" + line_of(v) +
                      ", " + type_name(*b) + " in its base " + base_file + line_of(*b) +
                      ": a key is a table in both files or in neither");
    if (b && b->is_table())
      merge_over(*b->as_table(), *v.as_table(), over_file, base_file, section.empty() ? key : section + "." + key);
    else
      merged.insert_or_assign(key, std::move(v));
  }
}

// A relative [surface] path of a base in another folder (`folder`, as the base key wrote it),
// made relative to the including file, so that it names the file the base means.
void rebase_surface_path(toml::table& t, const fs::path& folder) {
  toml::table* surface = t["surface"].as_table();
  toml::node* path = surface ? surface->get("path") : nullptr;
  if (folder.empty() || !path || !path->is_string()) return;
  const fs::path p(path->as_string()->get());
  if (p.is_relative()) surface->insert_or_assign("path", (folder / p).lexically_normal().string());
}

// The case file at `path` with its bases merged under it; `chain` holds the files on the
// way to it (canonical paths), for the cycle check.
toml::table read_with_bases(const std::string& path, const std::string& context, const std::string& also,
                            std::vector<fs::path>& chain) {
  toml::table t = read_toml_file(path, context, also);
  toml::node* b = t.get("base");
  if (!b) return t;
  if (!b->is_string())
    throw CaseError(path + ": base: expected the path of a base case file (a string), got " + type_name(*b) +
                    line_of(*b));
  const std::string value = b->as_string()->get();
  const std::string here = path + ": base = \"" + value + "\": ";
  std::error_code ec;
  fs::path base = fs::path(path).parent_path() / value;
  fs::path folder = fs::path(value).parent_path();  // the base's folder, seen from `path`
  const fs::path installed = fs::path(value).is_relative() ? data::root() : fs::path();
  if (!fs::exists(base, ec) && !installed.empty() && fs::exists(installed / value, ec)) {
    base = installed / value;
    folder = base.parent_path();
  }
  chain.push_back(fs::weakly_canonical(path, ec));
  if (std::find(chain.begin(), chain.end(), fs::weakly_canonical(base, ec)) != chain.end()) {
    std::string way;
    for (const auto& f : chain) way += f.filename().string() + " -> ";
    throw CaseError(here + "a cycle of bases (" + way + base.filename().string() +
                    "): a base cannot include a file on the way to it");
  }
  if (chain.size() > std::size_t(CaseLimits::kMaxBaseDepth))
    throw CaseError(here + "more than " + std::to_string(CaseLimits::kMaxBaseDepth) +
                    " bases deep (a base naming a base ...): expected a shallower chain");
  toml::table merged = read_with_bases(base.string(), here, also_looked(value), chain);
  chain.pop_back();
  rebase_surface_path(merged, folder);
  t.erase("base");
  merge_over(merged, t, path, base.string(), "");
  return merged;
}

}  // namespace

toml::table read_case_file(const std::string& path) {
  std::vector<fs::path> chain;
  return read_with_bases(data::find(path).string(), "", also_looked(path), chain);
}

Case load_case(const std::string& path, const std::vector<std::string>& overrides) {
  const std::string file = data::find(path).string();
  toml::table t = read_case_file(file);
  for (const auto& o : overrides) apply_override(t, o);
  return parse_case(t, file);
}

}  // namespace cmc
