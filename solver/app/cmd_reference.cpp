// cmc reference: regenerate (or verify) the stored analytic reference curves.
#include "commands.hpp"

#include "References.hpp"
#include "cmc/grid/FilePaths.hpp"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace cmc::app {

namespace {
const char* kReferenceHelp = R"(usage: cmc reference [NAME ...] [--out DIR] [--list] [--check]
       cmc reference --run-curve SPEC.toml --out FILE.csv

Writes the analytic reference curves (all of them, or the NAMEs given) as
DIR/NAME.csv in cmc's reference CSV format (see reference/README.md).
The default DIR is the reference/ folder of the source tree this cmc was built
from (or $CMC_REFERENCE_DIR).

  --list    print the names and titles of the curves, write nothing
  --check   compare the curves in DIR with freshly generated ones, write nothing;
            exit 5 if a file is missing or differs (byte for byte)

Analytic curves carry no date and no version, so regenerating them reproduces
the stored files byte for byte.

  --run-curve SPEC.toml   write one curve made of a cmc run's numbers (challenge
            references) to FILE.csv in the same format. SPEC: name, quantity, title,
            x, y, representation, estimated_error (strings); [provenance] cmc_version,
            case_file, grid, solver_tolerance, date, command; [[columns]] name, unit,
            meaning, values = [numbers]; optional extra = [["key", "value"], ...],
            written after the provenance (scripts/challenge_reference.py writes it);
            optional band = "COLUMN": the column holding y's uncertainty (a half-width
            > 0 in y's unit), which cmc check scores predictions against.
            FILE must be named NAME.csv, and the curve must be one cmc check reads
            as a reference (x strictly monotonic; positive values on log axes):
            otherwise exit 2 and nothing is written.
)";

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  if (!in) return {};
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

int cmd_reference(int argc, char** argv) {
  bool list = false, check = false;
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    const std::string s = argv[i];
    if (i >= 2 && s == "--list") list = true;
    else if (i >= 2 && s == "--check") check = true;
    else rest.push_back(argv[i]);
  }
  const Args a = parse_args(int(rest.size()), rest.data(), 2, {"--run-curve"});
  if (a.help) return std::fputs(kReferenceHelp, stdout), kOk;
  if (const std::string spec = a.option("--run-curve"); !spec.empty()) return write_run_curve(spec, a.out);
  if (!a.overrides.empty()) throw CaseError("cmc reference takes no --set (see cmc reference --help)");

  const auto all = reference::analytic_curve_names();
  std::vector<std::string> names = a.positional.empty() ? all : a.positional;
  for (const auto& n : names) {
    bool known = false;
    for (const auto& k : all) known |= k == n;
    if (!known) {
      std::string s;
      for (const auto& k : all) s += "\n  " + k;
      throw CaseError("unknown reference curve '" + n + "'; known curves:" + s);
    }
  }
  if (list) {
    for (const auto& n : names) std::printf("%-30s %s\n", n.c_str(), reference::analytic_curve_title(n).c_str());
    return kOk;
  }
  const std::filesystem::path dir = a.out.empty() ? reference::default_reference_dir() : a.out;
  if (!check) check_output_folder(dir);
  if (check) {
    int bad = 0;
    for (const auto& n : names) {
      const auto path = dir / (n + ".csv");
      const std::string want = reference::format_curve(reference::generate(n));
      const std::string have = slurp(path);
      const char* state = have.empty() ? "MISSING" : (have == want ? "ok" : "DIFFERS");
      if (have != want) ++bad;
      if (!a.quiet || have != want) std::printf("%-30s %s\n", n.c_str(), state);
    }
    if (bad) std::fprintf(stderr, "cmc reference: %d curve(s) in %s differ from the analytic module: run 'cmc reference'\n", bad, dir.c_str());
    return bad ? kValidationFailed : kOk;
  }
  for (const auto& n : names) {
    const auto path = dir / (n + ".csv");
    reference::write_curve(path.string(), reference::generate(n));
    if (!a.quiet) std::printf("wrote %s\n", path.c_str());
  }
  return kOk;
}

}  // namespace cmc::app
