// cmc refine: a grid-refinement study of one case (the challenge has no analytic
// reference, so its discretisation error is estimated from successive grids).
#include "commands.hpp"

#include "Refine.hpp"
#include "cmc/output/OutputLock.hpp"
#include "cmc/output/Writer.hpp"

#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>

namespace fs = std::filesystem;

namespace cmc::app {

namespace {
const char* kRefineHelp = R"(usage: cmc refine CASE.toml --grids N1 N2 [N3 ...] [--out DIR] [--set section.key=value ...] [--quiet]

Runs CASE.toml once per grid (--set grid.n=N, output.fields=false) into DIR/n<N>/
(a --set of grid.n, grid.nx or grid.ny is refused: exit 2)
(default DIR: results/refine/<case file stem>), exactly as `cmc run --resume` would:
a grid whose earlier run was interrupted continues from its last finished step, and a
grid whose run finished converged for the same case and --set values is not run again
(its record DIR/n<N>/refinement-grid.toml is reused). Then writes DIR/refinement.md and
DIR/refinement.json and prints the table: every scalar observable of the last load
step per grid, its relative change between successive grids (the change between the
two finest is the estimated discretisation error of the finest), the observed order of
the changes (three or more grids), and each grid's spacing relative to the surface's
short cutoff and the modes it drops.
Exit codes: 0 every grid converged, 2 bad input, 3 a grid did not converge (the
table is still written), 4 failed (I/O, memory, or DIR in use by another cmc process:
one process at a time writes into a folder).
)";

const char* kRecord = "refinement-grid.toml";

// The grid's record written after its run finished, if it is for this very case.
std::optional<RefinementGrid> finished(const fs::path& dir, const Case& c, int n) {
  if (!fs::exists(dir / kRecord)) return std::nullopt;
  toml::table t;
  try {
    t = toml::parse_file((dir / kRecord).string());
  } catch (const toml::parse_error&) {
    return std::nullopt;  // unreadable: run the grid again
  }
  if (t["case"].value_or(std::string()) != to_json(c.resolved) || t["n"].value_or(0) != n ||
      t["status"].value_or(std::string()) != "converged")
    return std::nullopt;
  RefinementGrid g{n, "converged", t["dx_m"].value_or(0.0), {}, {}};
  if (auto* s = t["last_step"].as_table()) g.last_step = *s;
  if (auto* f = t["facts"].as_table()) g.facts = *f;
  return g;
}

RefinementGrid run_grid(const fs::path& dir, const Case& c, int n, bool quiet) {
  print_memory_plan(c, quiet);
  Scene scene = build_scene(c);
  const RunSummary run = run_case_to(c, scene, dir.string(), /*resume=*/true, quiet);
  RefinementGrid g{n, status_name(run.status), scene.units.to_m(scene.grid.dx()), {}, {}};
  if (!run.steps.empty()) g.last_step = Writer::step_json(run.steps.back());
  for (const auto& [k, v] : surface_fact_entries(scene.surface_facts)) g.facts.insert(k, v);
  std::ostringstream rec;
  rec << toml::table{{"case", to_json(c.resolved)}, {"n", n},          {"status", status_name(run.status)},
                     {"dx_m", g.dx_m},             {"facts", g.facts}, {"last_step", g.last_step}}
      << "\n";
  write_output_text(dir / kRecord, rec.str());
  return g;
}

}  // namespace

int cmd_refine(int argc, char** argv) {
  std::vector<char*> rest;
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "-h" || std::string(argv[i]) == "--help") return std::fputs(kRefineHelp, stdout), kOk;
  const std::vector<int> grids = take_grids(argc, argv, rest);
  if (grids.size() < 2) throw CaseError("cmc refine needs --grids with at least two increasing grid sizes");
  const Args a = parse_args(int(rest.size()), rest.data(), 2);
  if (a.positional.size() != 1) throw CaseError("cmc refine takes exactly one case file (see cmc refine --help)");
  const std::string file = a.positional[0];
  refuse_grid_overrides(a.overrides, grids, "cmc refine");
  const fs::path out = a.out.empty() ? fs::path("results") / "refine" / fs::path(file).stem() : fs::path(a.out);
  // Every grid's case is read and checked (sizes, memory) before the first one runs.
  std::vector<Case> cases;
  for (int n : grids) {
    auto overrides = a.overrides;
    overrides.insert(overrides.begin(), {"grid.n=" + std::to_string(n), "output.fields=false"});
    cases.push_back(load_case(file, overrides));
    require_backend(cases.back());
  }
  const OutputLock lock(out);  // one study per folder (each grid's run locks its own too)
  // Every file the study writes, checked before the first grid runs (grid/FilePaths.hpp).
  for (const char* f : {"refinement.md", "refinement.json"}) check_output_file(out / f);
  for (int n : grids) check_output_file(out / ("n" + std::to_string(n)) / kRecord);
  std::vector<RefinementGrid> done;
  bool all_converged = true;
  for (std::size_t k = 0; k < grids.size(); ++k) {
    const int n = grids[k];
    const Case& c = cases[k];
    const fs::path dir = out / ("n" + std::to_string(n));
    auto g = finished(dir, c, n);
    if (g && !a.quiet) std::fprintf(stderr, "refine: n = %d: finished earlier, reusing %s\n", n, (dir / kRecord).c_str());
    if (!g) g = run_grid(dir, c, n, a.quiet);
    all_converged &= g->status == "converged";
    done.push_back(*g);
  }
  const auto rows = refinement_rows(done);
  const std::string md = refinement_markdown(file, done, rows);
  write_output_text(out / "refinement.md", md);
  write_output_text(out / "refinement.json", to_json(refinement_record(file, done, rows)));
  std::fputs(md.c_str(), stdout);
  return all_converged ? kOk : kNotConverged;
}

}  // namespace cmc::app
