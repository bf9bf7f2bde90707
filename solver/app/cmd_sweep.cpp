// cmc sweep: one case over a product of values (--over) and grids (--grids), each point
// run exactly as `cmc run` runs it, into a folder of its own; resumable.
#include "Sweep.hpp"
#include "commands.hpp"

#include "cmc/grid/FilePaths.hpp"
#include "cmc/output/CaseDiff.hpp"
#include "cmc/output/JsonRead.hpp"
#include "cmc/output/OutputLock.hpp"
#include "cmc/output/RunFolder.hpp"
#include "cmc/output/Writer.hpp"

#include <cstdio>
#include <filesystem>
#include <string>

namespace fs = std::filesystem;

namespace cmc::app {

namespace {
const char* kSweepHelp = R"(usage: cmc sweep CASE.toml --out DIR [--over section.key=V1,V2,... ...] [--grids N1 N2 ...]
                 [--set section.key=value ...] [--folder PATTERN] [--table NAME]
                 [--checkpoint-every SECONDS] [--dry-run] [--quiet]

Runs CASE.toml once per point: every combination of the values of each --over (several
--over make a product, the first one outermost) and of the grids of --grids (innermost;
--set grid.n=N for each). Values are TOML, as in --set (numbers, "strings" or bare words,
[arrays]); a comma inside brackets or quotes belongs to the value. At least one --over or
--grids. Each point runs into DIR/<its folder> exactly as
  cmc run CASE.toml --out DIR/<folder> --resume --set ... --set KEY=VALUE [--set grid.n=N]
would: the same code, the same summary.json (and result.h5), bit for bit.
Folders: --folder PATTERN, a relative path in which {KEY} stands for the point's value of
the swept KEY and {n} for its grid's points per side; default KEY_{KEY} per --over, nested,
then n{n} with --grids (e.g. DIR/interaction.tabor_0.1/n64). A value in a folder name keeps
letters, digits and . _ + -, loses a string's quotes, and has any other character as _.
Resumable: run the same command again after an interruption. A point whose folder holds a
converged run of the same case (the resolved case in its summary.json; case.description
aside) is not run again; one interrupted, or stopped at solver.max_outer_steps, continues
from its checkpoint (cmc run --resume); one that ended not converged with nothing to
continue is kept as it is (a rerun gives the same bits); a failed one without a checkpoint
runs again. A folder holding a run of another case is refused (exit 2) before any point
runs, and left as it is.
Then writes, atomically, DIR/sweep.json (one record per point: the swept values, grid,
status, folder, how it was reached, iterations and the steps' solve time summed over the
steps, and the last step's contact fraction, repulsive fraction, mean gap in m and mean
pressure in Pa) and DIR/sweep.md (the same as a Markdown table, also printed on stdout):
the points of this sweep (a later sweep into DIR replaces them; --table NAME writes
DIR/NAME.json and DIR/NAME.md instead, for several sweeps that share DIR).
Progress on stderr: a line per point; --quiet silences the runs' own progress lines.
--dry-run prints what each point would do (run, resume, skip, keep) and runs nothing.
--checkpoint-every: as cmc run's, for every point.
Refused before anything runs (exit 2, naming the argument): an unknown key or a malformed
value (each point's case is read and checked first), an empty list or value, a value or
key given twice, a --set of a swept key, grid.n/nx/ny in --set or --over beside --grids,
a folder pattern that gives two points one folder (or a point the table's name, .partial
or .cmc.lock), and a symbolic link on the way from DIR to a point's folder.
One cmc process at a time writes into DIR (DIR/.cmc.lock) and into each point's folder.
Exit codes: 0 every point converged, 2 bad input, 3 a point did not converge (the others
run; the table says which), 4 a point failed (the sweep stops there; the table is
written, with the points not run as "not_run").
)";

struct SweepRequest {
  std::string file, pattern, table;
  fs::path out;
  std::vector<SweepAxis> axes;
  std::vector<int> grids;
  std::vector<std::string> sets;
  double every = kCheckpointEverySeconds;
  bool quiet = false, dry_run = false;
};

// The axes: a key swept twice, fixed by a --set, or a grid key beside --grids is refused.
void check_axes(const SweepRequest& r) {
  for (std::size_t i = 0; i < r.axes.size(); ++i) {
    const std::string& key = r.axes[i].key;
    for (std::size_t j = 0; j < i; ++j)
      if (r.axes[j].key == key) throw CaseError("--over " + key + " is given twice: give its values in one --over");
    for (const auto& s : r.sets)
      if (override_key(s) == key)
        throw CaseError("--set " + s + " fixes the swept key " + key + " (--over): drop the --set, or the --over");
    if (is_grid_key(key) && !r.grids.empty())
      throw CaseError("--over " + key + "=... and --grids both set the grid: give the grids with one of them");
  }
  refuse_grid_overrides(r.sets, r.grids, "cmc sweep");
}

SweepRequest read_request(int argc, char** argv) {
  std::vector<char*> rest;
  SweepRequest r;
  r.grids = take_grids(argc, argv, rest);
  std::vector<char*> args;
  for (char* a : rest)
    if (std::string(a) == "--dry-run") r.dry_run = true;
    else args.push_back(a);
  const Args a = parse_args(int(args.size()), args.data(), 2, {"--over", "--folder", "--table", "--checkpoint-every"},
                            {"--over"});
  if (a.positional.size() != 1) throw CaseError("cmc sweep takes exactly one case file (see cmc sweep --help)");
  if (a.out.empty()) throw CaseError("cmc sweep needs --out DIR (see cmc sweep --help)");
  r.file = a.positional[0];
  r.out = a.out;
  r.sets = a.overrides;
  r.quiet = a.quiet;
  r.every = checkpoint_every(a);
  for (const auto& [name, value] : a.options)
    if (name == "--over") r.axes.push_back(parse_over(value));
  if (r.axes.empty() && r.grids.empty())
    throw CaseError("cmc sweep needs --over section.key=V1,V2,... or --grids N1 N2 ... (see cmc sweep --help)");
  check_axes(r);
  r.pattern = a.option("--folder", default_folder_pattern(r.axes, !r.grids.empty()));
  r.table = a.option("--table", "sweep");
  if (r.table.empty() || r.table.find('/') != std::string::npos || r.table == "." || r.table == "..")
    throw CaseError("--table '" + r.table + "': expected a file name without a folder (the table is DIR/NAME.json)");
  return r;
}

// Every point's case, read and checked (keys, values, memory, backend) before any runs: the
// case file (with its bases) is read once, each point's overrides applied to a copy of it, as
// load_case would (a sweep of 10,000 points reads one file, not 10,000).
std::vector<Case> load_point_cases(const SweepRequest& r, const std::vector<SweepPoint>& points) {
  std::vector<Case> cases;
  const toml::table file = read_case_file(r.file);
  for (const SweepPoint& p : points) {
    try {
      toml::table t = file;
      for (const std::string& o : p.sets) apply_override(t, o);
      cases.push_back(parse_case(t, r.file));
    } catch (const CaseError& e) {
      throw CaseError("cmc sweep, the point " + p.label() + ": " + e.what());
    }
    require_backend(cases.back());
  }
  return cases;
}

// Each point's folder, before anything runs: not the name of the sweep's table, and no link
// on the way from --out to it (a point is written into a folder of its own, not through one).
void check_point_folders(const SweepRequest& r, const std::vector<SweepPoint>& points) {
  for (const SweepPoint& p : points) {
    const fs::path folder(p.folder);
    const std::string first = folder.begin()->string();
    if (first == r.table + ".json" || first == r.table + ".md")
      throw CaseError("--folder " + r.pattern + ": the point " + p.label() + " gets the folder '" + p.folder +
                      "', where the sweep writes its table (--table " + r.table + "); expected another folder");
    fs::path at = r.out;
    for (const fs::path& part : folder) {
      at /= part;
      std::error_code ec;
      if (fs::is_symlink(fs::symlink_status(at, ec)))
        throw OutputPathError(at.string() + ": is a symbolic link; cmc sweep writes each point into a folder of its own "
                              "below --out, not through a link: remove it, or choose another --out");
    }
  }
}

// A refusal to resume a point, with the advice a sweep takes (there is no --resume to drop).
CaseError for_sweep(const CaseError& e, const fs::path& dir) {
  std::string text = e.what();
  const std::string drop = "run without --resume";
  const std::string instead = "remove " + (dir / ".partial").string() + " and run the sweep again";
  for (auto at = text.find(drop); at != std::string::npos; at = text.find(drop, at + instead.size()))
    text.replace(at, drop.size(), instead);
  return CaseError(text);
}

// What a point's folder asks for.
enum class Todo { Run, Resume, Done, Kept };

// The run in `dir`, against the point's case `c` (see kSweepHelp).
Todo plan_point(const fs::path& dir, const Case& c) {
  check_earlier_results(dir);  // cmc's own files only (exit 2 otherwise)
  std::error_code ec;
  const bool checkpoint = fs::exists(dir / ".partial" / "checkpoint.h5", ec);
  const fs::path file = dir / "summary.json";
  if (!fs::exists(file, ec)) return checkpoint ? Todo::Resume : Todo::Run;
  toml::table summary;
  try {
    summary = read_json_file(file);
  } catch (const JsonError& e) {
    throw OutputPathError(std::string(e.what()) + ": cmc sweep reuses only cmc's own runs; move it away or choose "
                          "another --out");
  }
  const toml::table* stored = summary["case"].as_table();
  const CaseDiff d = compare_cases(to_json(stored ? *stored : toml::table{}), to_json(c.resolved));
  const std::string status = summary["status"].value_or(std::string());
  if (d.same() && d.limits_changed.empty()) {
    if (status == "converged") return Todo::Done;
    if (status == "not_converged" && !checkpoint) return Todo::Kept;
    return checkpoint ? Todo::Resume : Todo::Run;  // failed: again (from its checkpoint, where it has one)
  }
  if (d.same() && checkpoint) return Todo::Resume;  // a changed stopping limit: the Writer decides (Writer.hpp)
  std::string why = d.same() ? d.limits_changed.front() : d.mismatch;
  for (auto at = why.find("the checkpoint"); at != std::string::npos; at = why.find("the checkpoint"))
    why.replace(at, 14, "that run");
  throw CaseError(file.string() + " holds a run of another case (" + why + "): cmc sweep reuses or continues only "
                  "a run of the point's own case; move it away or choose another --out");
}

const char* todo_words(Todo t, bool dry_run) {
  switch (t) {
    case Todo::Run: return dry_run ? "would run" : "running";
    case Todo::Resume: return dry_run ? "would resume" : "resuming";
    case Todo::Done: return "converged earlier: skipped";
    case Todo::Kept: return "not converged earlier, nothing to continue: kept";
  }
  return "?";
}

// Runs (or reuses) one point and reads its result back from its summary.json.
PointResult run_point(const SweepRequest& r, const SweepPoint& p, const Case& c, Todo todo) {
  const fs::path dir = r.out / p.folder;
  std::string how = todo == Todo::Done ? "done earlier" : todo == Todo::Kept ? "kept" : todo == Todo::Resume ? "resumed" : "ran";
  if (todo == Todo::Run || todo == Todo::Resume) {
    try {
      run_case_folder(c, dir.string(), todo == Todo::Resume, r.quiet, r.every);
    } catch (const RunStopped& e) {  // stopped at the same limit again: the folder is as it was
      std::fprintf(stderr, "cmc sweep: %s\n", e.what());
      how = "kept";
    } catch (const CaseError& e) {
      if (todo == Todo::Resume) throw for_sweep(e, dir);
      throw;
    }
  }
  return point_result(read_json_file(dir / "summary.json"), how);
}

// A point whose run threw: what its summary.json says (a failed run writes one), failed.
PointResult failed_result(const fs::path& dir, const std::string& what) {
  PointResult p;
  try {
    p = point_result(read_json_file(dir / "summary.json"), "ran");
  } catch (const JsonError&) {  // none, or unreadable: the message says it all
  }
  p.status = "failed";
  p.message = what;
  return p;
}

void write_tables(const SweepRequest& r, const std::vector<SweepPoint>& points, const std::vector<PointResult>& results,
                  bool print) {
  const SweepTable t{r.file, r.pattern, r.axes, r.grids, r.sets};
  write_output_text(r.out / (r.table + ".json"), sweep_json(t, points, results));
  const std::string md = sweep_markdown(t, points, results);
  write_output_text(r.out / (r.table + ".md"), md);
  if (print) std::fputs(md.c_str(), stdout);
}

// The points in order; a failed point stops the sweep after the tables are written.
int run_points(const SweepRequest& r, const std::vector<SweepPoint>& points, const std::vector<Case>& cases,
               const std::vector<Todo>& todo) {
  std::vector<PointResult> results(points.size());
  bool all_converged = true;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string dir = (r.out / points[i].folder).string();
    std::fprintf(stderr, "sweep: point %zu/%zu (%s): %s -> %s\n", i + 1, points.size(), points[i].label().c_str(),
                 todo_words(todo[i], false), dir.c_str());
    try {
      results[i] = run_point(r, points[i], cases[i], todo[i]);
    } catch (const std::exception& e) {
      results[i] = failed_result(dir, e.what());
      write_tables(r, points, results, false);
      throw;
    }
    const PointResult& p = results[i];
    all_converged &= p.status == "converged";
    if (todo[i] == Todo::Run || todo[i] == Todo::Resume)
      std::fprintf(stderr, "sweep: point %zu/%zu (%s): %s, %lld iterations, %.1f s%s%s\n", i + 1, points.size(),
                 points[i].label().c_str(), p.status.c_str(), p.iterations, p.wall_s, p.message.empty() ? "" : ": ",
                 p.message.c_str());
  }
  write_tables(r, points, results, true);
  return all_converged ? kOk : kNotConverged;
}

}  // namespace

int cmd_sweep(int argc, char** argv) {
  for (int i = 2; i < argc; ++i)
    if (std::string(argv[i]) == "-h" || std::string(argv[i]) == "--help") return std::fputs(kSweepHelp, stdout), kOk;
  const SweepRequest r = read_request(argc, argv);
  std::vector<SweepPoint> points = sweep_points(r.axes, r.grids, r.sets);
  const std::vector<Case> cases = load_point_cases(r, points);
  sweep_folders(points, cases, r.pattern);
  check_point_folders(r, points);
  // Every folder and file the sweep writes, checked before the first point runs.
  check_output_folder(r.out);
  for (const char* ext : {".json", ".md"}) check_output_file(r.out / (r.table + ext));
  std::vector<Todo> todo;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const fs::path dir = r.out / points[i].folder;
    std::error_code ec;
    if (fs::symlink_status(dir, ec).type() == fs::file_type::not_found) {  // nothing there yet: a run
      todo.push_back(Todo::Run);
      continue;
    }
    check_output_folder(dir);
    todo.push_back(plan_point(dir, cases[i]));
  }
  if (r.dry_run) {
    for (std::size_t i = 0; i < points.size(); ++i)
      std::printf("sweep: point %zu/%zu (%s): %s -> %s\n", i + 1, points.size(), points[i].label().c_str(),
                  todo_words(todo[i], true), (r.out / points[i].folder).c_str());
    return kOk;
  }
  const OutputLock lock(r.out);  // one sweep per folder (each point's run locks its own too)
  return run_points(r, points, cases, todo);
}

}  // namespace cmc::app
