// cmc check: score a submitted prediction (CSV) against a reference curve.
#include "commands.hpp"

#include "Check.hpp"
#include "cmc/input/DataDir.hpp"
#include "cmc/output/Writer.hpp"

#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

extern char** environ;

namespace cmc::app {

namespace {
const char* kCheckHelp = R"(usage: cmc check PREDICTION.csv --quantity Q [--adhesionless] [--against WHICH] [--reference FILE]
                 [--out DIR] [--tolerance T] [--metric M] [--min-coverage F] [--columns A,B,...]
       cmc check PREDICTION.csv --reference FILE [--x COL --y COL] [--out DIR] ...
       cmc check --list

Compares a predicted curve or distribution with a reference curve over their
common range, interpolating in the representation the challenge asks for (log
axes where it says so), prints the errors and a verdict, and with --out writes
DIR/check.json and the overlay figure DIR/check.png (reports/plot_check.py).

PREDICTION.csv: one quantity per file, one row per point; '#' lines are comments.
Layouts understood (those of the challenge's submissions):
  - values separated by commas, semicolons, tabs or spaces (runs of spaces count
    as one); the first non-comment line decides, and every row follows it;
  - a header row naming the columns: the names say the quantity and the unit,
    SI or reduced, e.g. pressure_Pa,contact_fraction or p_over_Estar contact_fraction
    (cmc check --list gives every name and unit; reference/README.md);
  - no header row (the first line is numbers): name the columns with
    --columns, e.g. --columns pressure_Pa,contact_fraction. --columns also
    renames the columns of a file whose header uses other names.
Extra columns are ignored; rows may run up or down the abscissa.

  --quantity Q    a challenge quantity (cmc check --list); its stored reference is
                  reference/challenge/Q.csv (where it exists; else --reference is needed)
  --adhesionless  with --quantity: score against the same surface without adhesion
                  (hard wall; reference/challenge/adhesionless/Q.csv), for the
                  quantities that have one (not those against the Tabor parameter)
  --against WHICH with --quantity: which question the prediction answers, and so which
                  stored reference it is scored against:
                    surface      cmc's own surface (reference/challenge/Q.csv): a run
                                 on the surface `cmc surface --write` gives
                    ensemble     the mean over all surfaces of the spectrum
                                 (reference/challenge/ensemble/Q.csv): a theory
                    realisation  any one surface of the spectrum, e.g. the organisers'
                                 (reference/challenge/realisation/Q.csv): a run on
                                 another surface; the default where that reference
                                 exists (else surface, and the report says so)
  --reference F   the reference curve (cmc reference CSV format); without
                  --quantity the columns are matched by name (--x/--y, default the
                  reference's x and y) and no units are converted
  --tolerance T   tolerance for the verdict (default: the reference's, else the
                  quantity's default)
  --metric M      max_abs | rms_abs | max_rel | rms_rel (default: as the tolerance)
                  A reference with an error band ('# band: COLUMN', its own
                  uncertainty) is scored against it unless --tolerance or --metric
                  is given: PASS inside the band, else FAIL saying by how much, in
                  units of the band (max_band).
  --columns A,B,...  names for the prediction's columns, in file order (for a
                  file without a header row, or to replace its header's names)
  --min-coverage F  the fraction of the reference's range (on its abscissa, in the
                  representation) the prediction must cover, 0 to 1 (default: the
                  reference's '# min_coverage:', else 0.5); less is a FAIL

The prediction is read row by row (any size); check.json echoes at most 1000 of its
rows and of the evaluation points, evenly sampled, and says so.

Errors: max and rms of the difference in the representation (abs: decades on a
log y axis, SI units on a linear one; rel: |y_pred/y_ref - 1| on a log y axis,
|difference|/max|y_ref| on a linear one).
Exit codes: 0 pass, 5 fail, 2 bad input (nothing is written).
)";

void list_quantities() {
  std::printf("%-26s %-8s %s\n", "quantity", "axes", "columns (stem_unit; first stem preferred)");
  for (const auto& q : check::quantities()) {
    auto names = [](const check::AxisSpec& a) {
      std::string stems, us;
      for (const auto& b : a.bases) stems += (stems.empty() ? "" : "|") + b;
      for (const auto& u : check::units(a.dim)) us += (us.empty() ? "" : "|") + (u.suffix.empty() ? "(none)" : u.suffix);
      return stems + "  _  " + us + "  [" + check::si_unit(a.dim) + "]";
    };
    std::printf("%-26s %-8s x: %s\n", q.id.c_str(), check::representation_name(q.rep).c_str(), names(q.x).c_str());
    std::printf("%-26s %-8s y: %s\n", "", "", names(q.y).c_str());
    std::printf("%-26s %-8s default tolerance %g on %s; challenge item %d: %s\n", "", "", q.tolerance,
                q.metric.c_str(), q.item, q.title.c_str());
    std::error_code ec;
    auto stored = [&](bool adhesionless) {
      return std::filesystem::exists(check::default_reference_path(q.id, adhesionless), ec) ? "yes" : "no";
    };
    std::printf("%-26s %-8s stored reference: with adhesion %s, adhesionless (--adhesionless) %s\n", "", "",
                stored(false), stored(true));
  }
}

// reports/plot_check.py in $CMC_REPORTS_DIR, else in cmc's data folder (the checkout, or
// PREFIX/share/cmc once installed; input/DataDir.hpp).
std::string plot_script() {
  if (const char* d = std::getenv("CMC_REPORTS_DIR"); d && *d) return std::string(d) + "/plot_check.py";
  return (data::root() / "reports" / "plot_check.py").string();
}

// Draws the overlay with /usr/bin/python3 (or $CMC_PYTHON). A missing interpreter or
// matplotlib only costs the figure: say so on stderr.
void draw_figure(const std::filesystem::path& json, const std::filesystem::path& png, bool quiet) {
  const char* env = std::getenv("CMC_PYTHON");
  const std::string python = env && *env ? env : "/usr/bin/python3";
  const std::string script = plot_script();
  if (::access(python.c_str(), X_OK) != 0) {
    std::fprintf(stderr, "cmc check: %s not found: no figure drawn (check.json is written; install python3-matplotlib)\n",
                 python.c_str());
    return;
  }
  if (::access(script.c_str(), R_OK) != 0) {
    const std::string looked = data::root().empty() ? "; " + data::places_text() : "";
    std::fprintf(stderr, "cmc check: %s not found%s: no figure drawn (check.json is written)\n", script.c_str(),
                 looked.c_str());
    return;
  }
  std::vector<std::string> args = {python, script, json.string(), png.string()};
  std::vector<char*> argv;
  for (auto& s : args) argv.push_back(s.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  if (posix_spawn(&pid, python.c_str(), nullptr, nullptr, argv.data(), environ) != 0) {
    std::fprintf(stderr, "cmc check: could not start %s: no figure drawn\n", python.c_str());
    return;
  }
  int status = 0;
  waitpid(pid, &status, 0);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    if (!quiet) std::printf("figure          %s\n", png.c_str());
  } else {
    std::fprintf(stderr, "cmc check: %s failed (exit %d): no figure drawn (check.json is written)\n", script.c_str(),
                 WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  }
}
}  // namespace

int cmd_check(int argc, char** argv) {
  bool list = false, adhesionless = false;
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    if (i >= 2 && std::string(argv[i]) == "--list") list = true;
    else if (i >= 2 && std::string(argv[i]) == "--adhesionless") adhesionless = true;
    else rest.push_back(argv[i]);
  }
  const Args a = parse_args(int(rest.size()), rest.data(), 2,
                            {"--quantity", "--reference", "--tolerance", "--metric", "--x", "--y", "--min-coverage", "--columns",
                             "--against"});
  if (a.help) return std::fputs(kCheckHelp, stdout), kOk;
  if (list) return list_quantities(), kOk;
  if (!a.overrides.empty()) throw CaseError("cmc check takes no --set (see cmc check --help)");
  if (a.positional.size() != 1)
    throw CaseError("cmc check needs exactly one prediction file (see cmc check --help)");
  check::Options o;
  o.prediction = a.positional[0];
  o.quantity = a.option("--quantity");
  o.adhesionless = adhesionless;
  o.against = a.option("--against");
  o.reference_file = a.option("--reference");
  o.metric = a.option("--metric");
  o.x = a.option("--x");
  o.y = a.option("--y");
  if (const std::string cols = a.option("--columns"); !cols.empty()) {
    std::string cur;
    for (char ch : cols + ",") {
      if (ch != ',') {
        cur += ch;
        continue;
      }
      if (cur.empty()) throw CaseError("--columns " + cols + ": expected comma-separated column names, none empty");
      o.columns.push_back(cur);
      cur.clear();
    }
    if (o.columns.size() < 2) throw CaseError("--columns " + cols + ": expected at least two column names");
  }
  if (const std::string t = a.option("--tolerance"); !t.empty()) {
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (end == t.c_str() || *end != '\0' || !(v > 0) || !std::isfinite(v))
      throw CaseError("--tolerance " + t + ": expected a positive number");
    o.tolerance = v;
  }
  if (const std::string t = a.option("--min-coverage"); !t.empty()) {
    char* end = nullptr;
    const double v = std::strtod(t.c_str(), &end);
    if (end == t.c_str() || *end != '\0' || !(v >= 0.0 && v <= 1.0))
      throw CaseError("--min-coverage " + t + ": expected a fraction from 0 to 1");
    o.min_coverage = v;
  }
  const std::filesystem::path dir(a.out);
  if (!a.out.empty()) {  // before anything is scored or printed
    check_output_folder(dir);
    for (const char* f : {"check.json", "check.png"}) check_output_file(dir / f);
  }
  check::Report r;
  try {
    r = check::run_check(o);
  } catch (const check::InputError& e) {
    std::fprintf(stderr, "cmc check: error: %s\n", e.what());
    return kUsage;
  }
  std::fputs(check::report_text(r).c_str(), stdout);
  if (!a.out.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir))
      throw std::runtime_error(dir.string() + ": cannot create the output folder");
    write_output_text(dir / "check.json", check::report_json(r));
    if (!a.quiet) std::printf("wrote           %s\n", (dir / "check.json").c_str());
    draw_figure(dir / "check.json", dir / "check.png", a.quiet);
  }
  return r.verdict.pass ? kOk : kValidationFailed;
}

}  // namespace cmc::app
