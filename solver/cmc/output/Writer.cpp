// A run's folder (Writer.hpp): the summary (summary.json) and the order of writing; the
// result files are written by output/ResultFiles.cpp, checkpoints by output/Checkpoint.cpp.
#include "cmc/output/Writer.hpp"

#include "cmc/grid/Backend.hpp"
#include "cmc/grid/Ranks.hpp"
#include "cmc/output/Hdf5Fields.hpp"
#include "cmc/output/Records.hpp"
#include "cmc/output/ResultFiles.hpp"
#include "cmc/output/RunFolder.hpp"
#include "cmc/scene/SceneNeeds.hpp"

#include <hdf5.h>

#include <cstdio>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace cmc {

namespace fs = std::filesystem;

std::string to_json(const toml::table& t) {
  std::ostringstream s;
  s << toml::json_formatter{t} << "\n";
  return s.str();
}

namespace {

toml::table timing_table(const RunSummary& run) {
  return toml::table{{"wall_s", run.wall_s},
                     {"fft_pairs", run.fft_pairs},
                     {"iterations", run.iterations},
                     {"fft_pair_s", run.fft_pair_s},
                     {"time_per_fft_pair", run.time_per_fft_pair},
                     {"time_per_iteration", run.time_per_iteration},
                     {"row_column_pair_s", run.row_column_pair_s},
                     {"floor_pair_s", run.floor_pair_s},
                     {"time_per_floor_pair", run.time_per_floor_pair},
                     {"fft_share", run.fft_share}};
}

toml::table load_path_table(const RunSummary& run) {
  return toml::table{{"pulloff_mean_pressure", run.pulloff_mean_pressure},
                     {"pulloff_force", run.pulloff_force},
                     {"pulloff_branch", run.pulloff_branch ? records::branch_name(*run.pulloff_branch) : ""},
                     {"halved_steps", run.halved_steps},
                     {"jumps", run.jumps}};
}

// What the scene needed and left out (scene/SceneNeeds.hpp), the fields the solver holds
// (counted) and the most bytes the process's fields held up to the end of the run (measured).
toml::table model_table(const Case& c) {
  const SceneNeeds n = scene_needs(c);
  toml::array left_out;
  for (const auto& w : n.left_out) left_out.push_back(w);
  const SolverFields& f = n.solver_fields;
  return toml::table{{"interaction", n.interaction}, {"adhesion", n.adhesion}, {"solver", n.solver},
                     {"observables", n.observables}, {"fields_written", n.fields_written},
                     {"boundary", n.boundary}, {"precision", n.precision}, {"left_out", left_out},
                     {"solver_fields", toml::table{{"run_grid", f.run_grid}, {"run_transform", f.run_transform},
                                                   {"solve_grid", f.solve_grid},
                                                   {"solve_transform", f.solve_transform}}},
                     {"field_bytes_peak", (long long)field_bytes_peak()},
                     {"memory_estimate_bytes", estimate_memory(c).bytes}};
}

}  // namespace

Writer::Writer(fs::path dir, const Case& c, const Scene& s, bool resume)
    : lock_(is_root() ? OutputLock(dir) : OutputLock()), dir_(std::move(dir)), case_(c), scene_(s) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  partial_ = dir_ / ".partial";
  checkpoint_ = partial_ / "checkpoint.h5";
  marker_ = dir_ / "INCOMPLETE";
  std::error_code ec;
  // In a distributed run rank 0 alone touches the folder; every rank takes part in
  // reading a checkpoint (load_partial) and in writing fields (dataset()).
  const bool have_checkpoint = any_rank(is_root() && fs::exists(checkpoint_));
  if (resume) {
    if (have_checkpoint) {
      load_partial();
      resuming_ = true;
    } else if (is_root() && fs::exists(dir_ / ".progress.toml")) {
      notice_ = dir_.string() + " held a partial run written by an earlier version of cmc (.progress.toml), which "
                "cannot be continued exactly: starting afresh";
    }
  }
  if (!is_root()) return;
  clear_earlier_results(dir_);  // an earlier run's results must not pass for this run's
  // A run that stopped at its outer-step limit goes on now: it is unfinished again.
  if (resuming_) fs::remove(partial_ / "stopped.toml", ec);
  if (!resuming_) {
    for (const char* f : {".progress.toml", ".checkpoint.h5", ".result.h5.partial"}) fs::remove(dir_ / f, ec);
    fs::remove_all(partial_, ec);
    fs::create_directories(partial_, ec);
    if (ec || !fs::is_directory(partial_)) throw std::runtime_error(partial_.string() + ": cannot create the folder");
  }
  write_output_text(marker_, incomplete_text(c, dir_));
}

fs::path Writer::step_file(int index) const {
  char name[32];
  std::snprintf(name, sizeof name, "step_%04d.h5", index);
  return partial_ / name;
}

Writer::~Writer() = default;

bool Writer::stopped_at_limit(const StepRecord& rec) const {
  return case_.solver.kind == SolverKind::QuasiStatic && !rec.result.converged &&
         rec.result.message.rfind(kOuterLimitMessage, 0) == 0;
}

void Writer::add_step(const StepRecord& rec, const ContactState& st) {
  // From the first step stopped at its limit on, the checkpoint stays where it is: the
  // last one before that stop, from which a larger limit continues (finish() keeps it).
  if (stopped_step_ < 0 && stopped_at_limit(rec)) stopped_step_ = rec.index;
  if (writes_step_files()) {
    // The step's fields and observables in a file of its own, written atomically: kept only
    // when a checkpoint names the step (a step redone after an interruption replaces it). In
    // a distributed run every rank sends rank 0 its slabs (`tmp` is rank 0's).
    auto fill = [&](const fs::path& tmp) { write_step_file(tmp, rec, st, scene_, case_.write_fields); };
    if (is_root()) write_output_file(step_file(rec.index), fill);
    else fill({});
  }
  records_.push_back(step_json(rec));
}

toml::table Writer::step_json(const StepRecord& r) {
  toml::table t{{"index", r.index},
                     {"branch", records::branch_name(r.branch)},
                     {"mean_pressure", r.mean_pressure},
                     {"force", r.force},
                     {"penetration", r.penetration},
                     {"mean_gap", r.mean_gap},
                     {"contact_fraction", r.contact_fraction},
                     {"energy", r.energy},
                     {"iterations", r.result.iterations},
                     {"converged", r.result.converged},
                     {"residual", r.result.residual},
                     {"wall_s", r.result.wall_s},
                     {"fft_pairs", r.result.fft_pairs},
                     {"fft_s", r.result.fft_s},
                     {"jump", r.jump},
                     {"halvings", r.halvings},
                     {"message", r.result.message}};
  t.insert("diagnostics", records::diagnostics_table(r.result.diagnostics));
  if (r.observables) {
    toml::table o;
    for (const auto& [k, v] : r.observables->scalars) o.insert(k, v);
    t.insert("observables", o);
  }
  return t;
}

// Where the transforms ran: on the CPU, FFTW's plans; on the GPU, cuFFT for the
// Polonsky-Keer iterations (and the device), FFTW for what stays on the host (the
// quasi-static solver's outer steps).
std::string Writer::fft_plans() const {
  const HalfSpace& hs = *scene_.half_space;
  const std::string host = hs.plan_source();
  if (case_.grid.backend != "cuda") return hs.solver_plans().empty() ? host : host + "; " + hs.solver_plans();
  std::string device;
  try {
    device = cuda::device_description();
  } catch (const std::exception& e) {
    device = e.what();
  }
  // The solve's transforms run on the device (the quasi-static solver's outer steps too);
  // the host's plans make the set-up (K's unit response) and the observables.
  return "cuFFT on " + device + " (the solve); " + host + " (host: set-up and observables)";
}

toml::table Writer::summary_base() const {
  const Units& u = scene_.units;
  const Grid& g = scene_.grid;
  toml::table base{
      {"cmc_version", CMC_VERSION},
      {"case_file", case_.file},
      {"case", case_.resolved},
      {"units",
       toml::table{{"length", "m"}, {"pressure", "Pa"}, {"force", "N"}, {"energy", "J"},
                   {"reduced_length_unit_m", u.length_m}, {"reduced_pressure_unit_pa", u.pressure_pa}}},
      {"grid", toml::table{{"nx", g.nx}, {"ny", g.ny}, {"size_x", u.to_m(g.lx)}, {"size_y", u.to_m(g.ly)},
                           {"dx", u.to_m(g.dx())}, {"dy", u.to_m(g.dy())},
                           {"boundary", scene_.half_space->periodic() ? "periodic" : "free"},
                           {"fft_size", (long long)scene_.half_space->transform_points()},
                           {"mpi_ranks", ranks()},
                           {"threads", thread_count()},
                           {"backend", case_.grid.backend},
                           {"fft_plans", fft_plans()},
                           {"fft_wisdom_fingerprint", builtin_wisdom_fingerprint()}}},
      {"surface", scene_.topography.description},
  };
  toml::table facts;
  for (const auto& [k, v] : surface_fact_entries(scene_.surface_facts)) facts.insert(k, v);
  if (!facts.empty()) base.insert("surface_facts", facts);
  base.insert("model", model_table(case_));
  toml::array warnings;
  for (const auto& w : scene_.warnings) warnings.push_back(w);
  base.insert("warnings", warnings);
  if (!start_.empty()) base.insert("start_from", start_);
  return base;
}

void Writer::finish(const RunSummary& run, const toml::table& extra) {
  toml::table s = summary_base();
  s.insert("status", status_name(run.status));
  // A step stopped at its outer-step limit, with a checkpoint from before that stop: kept.
  const bool keep = stopped_step_ >= 0 && is_root() && fs::exists(checkpoint_);
  const int limit = case_.solver.max_outer_steps;
  s.insert("message", run.message + (keep ? " (its checkpoint is kept: resume with a larger solver.max_outer_steps "
                                            "to continue it, see \"continue\")"
                                          : ""));
  if (keep)
    s.insert("continue",
             toml::table{{"step", stopped_step_},
                         {"max_outer_steps", limit},
                         {"checkpoint", ".partial/checkpoint.h5"},
                         {"how", "the command of this run (case file, --out and --set options) with --resume "
                                 "--set solver.max_outer_steps=N, any N above " +
                                     std::to_string(limit) + " (e.g. " + std::to_string(2 * limit) + ")"}});
  s.insert("timing", timing_table(run));
  toml::array steps;
  for (const auto& r : run.steps) steps.push_back(step_json(r));
  s.insert("steps", steps);
  if (run.load_path) s.insert("load_path", load_path_table(run));
  for (const auto& [k, v] : extra) s.insert_or_assign(k, v);
  if (!is_root()) {  // the heights' slabs go to rank 0, which writes everything
    if (case_.write_fields) h5::dataset(-1, "heights", scene_.grid, scene_.topography.heights, 1.0, "", "");
    return;
  }
  if (writes_step_files()) {
    // result.h5: the heights, then every step's group copied from its file; result.xdmf
    // where there are fields for ParaView to show.
    std::vector<fs::path> step_files;
    for (const auto& r : run.steps) step_files.push_back(step_file(r.index));
    write_output_file(dir_ / "result.h5", [&](const fs::path& tmp) {
      write_result_file(tmp, case_, scene_, run.steps, step_files, case_.write_fields);
    });
    if (case_.write_fields) write_output_text(dir_ / "result.xdmf", xdmf_text(run.steps, scene_));
  }
  // Says which limit stopped it: a resume must raise that limit (load_partial). The fields
  // of the stopped step and those after it are in result.h5; a resume redoes them.
  if (keep) {
    std::error_code gone;
    for (const auto& r : run.steps)
      if (r.index >= stopped_step_) fs::remove(step_file(r.index), gone);
    write_output_text(partial_ / "stopped.toml", "max_outer_steps = " + std::to_string(limit) +
                                                    "\nstep = " + std::to_string(stopped_step_) + "\n");
  }
  write_output_text(dir_ / "summary.json", to_json(s));
  // The run is complete: its partial files go, unless it can be continued.
  std::error_code ec;
  fs::remove(marker_, ec);
  if (!keep) fs::remove_all(partial_, ec);
}

void Writer::fail(const std::string& message) {
  if (!is_root()) return;
  // Results of an earlier run in the same folder must not pass for this run's.
  std::error_code ec;
  for (const char* f : {"result.h5", "result.xdmf"}) fs::remove(dir_ / f, ec);
  toml::table s = summary_base();
  s.insert("status", status_name(RunStatus::Failed));
  s.insert("message", message + (records_.empty() ? "" : " (the finished steps can be continued with --resume)"));
  write_output_text(dir_ / "summary.json", to_json(s));
}

}  // namespace cmc
