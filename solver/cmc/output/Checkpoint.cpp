// A run's checkpoint (.partial/checkpoint.h5, Writer.hpp): written at every point the run
// can be continued from (Writer::checkpoint), read back by --resume (Writer::load_partial).
#include "cmc/output/Writer.hpp"

#include "cmc/grid/Ranks.hpp"
#include "cmc/output/CaseDiff.hpp"
#include "cmc/output/Hdf5Fields.hpp"
#include "cmc/output/Records.hpp"
#include "cmc/output/RunFolder.hpp"
#include "cmc/surface/H5Handle.hpp"

#include <fstream>
#include <sstream>
#include <type_traits>
#include <utility>

namespace cmc {

namespace fs = std::filesystem;
using h5::NamedField;

namespace {

CaseError damaged(const std::string& file, const std::string& what) {
  return CaseError(file + ": " + what + " (a damaged checkpoint of a partial run); run without --resume to start afresh");
}

template <class State, class F = std::conditional_t<std::is_const_v<State>, const Field, Field>>
std::vector<NamedField<F>> state_fields(State& st) {
  return {{"pressure", &st.pressure, "E*"}, {"displacement", &st.displacement, "L"}, {"gap", &st.gap, "L"}};
}
// Where a quasi-static solve stood inside a step: Polonsky-Keer's warm-start pressure and
// the tension (QuasiStaticAdhesion.hpp, OuterPoint).
template <class Point, class F = std::conditional_t<std::is_const_v<Point>, const Field, Field>>
std::vector<NamedField<F>> inside_fields(Point& at) {
  return {{"pressure", &at.inner.pressure, "E*"}, {"tension", &at.tension, "E*"}};
}

const char* refinement_name(PathState::Refinement r) {
  switch (r) {
    case PathState::Refinement::NotStarted: return "not_started";
    case PathState::Refinement::Running: return "running";
    case PathState::Refinement::Done: return "done";
  }
  return "?";
}

// Every scalar of a PathState with its name in the checkpoint (its fields are in
// `pulloff` of the checkpoint file): one list for writing and reading.
template <class P, class F>
void path_scalars(P& p, F&& f) {
  f("started", p.started), f("next", p.next), f("have_prev", p.have_prev), f("value", p.value);
  f("contact_fraction", p.contact_fraction), f("mean_pressure", p.mean_pressure);
  f("pressure_scale", p.pressure_scale), f("branch", p.branch);
  f("pulloff_mean_pressure", p.pulloff_mean_pressure), f("pulloff_value", p.pulloff_value);
  f("pulloff_branch", p.pulloff_branch), f("pulloff_before", p.pulloff_before), f("pulloff_after", p.pulloff_after);
  f("pulloff_is_last", p.pulloff_is_last), f("have_last", p.have_last), f("last_value", p.last_value);
  f("pulloff_state_penetration", p.pulloff_state.penetration);
  f("pulloff_state_mean_pressure", p.pulloff_state.mean_pressure);
  f("failed_steps", p.failed_steps), f("halved_steps", p.halved_steps), f("jumps", p.jumps);
  f("max_halvings", p.max_halvings), f("refinement", p.refinement), f("lo", p.lo), f("hi", p.hi), f("x1", p.x1);
  f("x2", p.x2), f("f1", p.f1), f("f2", p.f2), f("have_f1", p.have_f1), f("have_f2", p.have_f2);
  f("refinement_solves", p.refinement_solves);
}

toml::table path_table(const PathState& p) {
  toml::table t;
  path_scalars(p, [&](const char* key, const auto& v) {
    using T = std::decay_t<decltype(v)>;
    if constexpr (std::is_same_v<T, Branch>) t.insert(key, records::branch_name(v));
    else if constexpr (std::is_same_v<T, PathState::Refinement>) t.insert(key, refinement_name(v));
    else if constexpr (std::is_same_v<T, bool> || std::is_same_v<T, double>) t.insert(key, v);
    else t.insert(key, (long long)v);
  });
  t.insert("pulloff_state", !p.pulloff_state.empty());
  return t;
}

PathState path_from(const toml::table& t, const std::string& file) {
  PathState p;
  path_scalars(p, [&](const char* key, auto& v) {
    using T = std::decay_t<decltype(v)>;
    auto bad = [&](const char* expected) {
      return CaseError(file + ": key 'path." + key + "': expected " + expected +
                       " (a damaged checkpoint); run without --resume to start afresh");
    };
    const auto node = t[key];
    if constexpr (std::is_same_v<T, Branch>) {
      v = records::branch_named(node.value_or(std::string()), file);
    } else if constexpr (std::is_same_v<T, PathState::Refinement>) {
      const std::string name = node.value_or(std::string());
      bool found = false;
      for (auto r : {PathState::Refinement::NotStarted, PathState::Refinement::Running, PathState::Refinement::Done})
        if (name == refinement_name(r)) v = r, found = true;
      if (!found) throw bad("\"not_started\", \"running\" or \"done\"");
    } else if constexpr (std::is_same_v<T, bool>) {
      const auto b = node.template value<bool>();
      if (!b) throw bad("true or false");
      v = *b;
    } else if constexpr (std::is_same_v<T, double>) {
      const auto* d = node.as_floating_point();
      if (!d) throw bad("a floating-point number");
      v = d->get();
    } else {
      const auto* i = node.as_integer();
      if (!i || i->get() < 0) throw bad("a non-negative integer");
      v = T(i->get());
    }
  });
  return p;
}

// The checkpoint's record of where the run stands (dataset 'progress'). Rank 0 reads the
// file and keeps it open in `f` for the fields; every rank parses the same text (a problem
// found on rank 0 travels as the text "!" plus the message, so that every rank stops alike).
toml::table read_progress(const fs::path& checkpoint, H5Handle& f) {
  const std::string file = checkpoint.string();
  std::string text;
  if (is_root()) {
    f = H5Handle(H5Fopen(checkpoint.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!f.ok()) text = "!not a readable HDF5 file";
    else if (!h5::read_text(f, "progress", text)) text = "!no dataset 'progress'";
  }
  broadcast(text);
  if (!text.empty() && text[0] == '!') throw damaged(file, text.substr(1));
  toml::table t;
  try {
    t = toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    throw damaged(file, "dataset 'progress' is not TOML (" + std::string(e.description()) + ")");
  }
  if (t["format"].value_or(0) != 1) throw damaged(file, "key 'format': expected 1 (written by another version of cmc?)");
  return t;
}

// A finished run that stopped at its outer-step limit (finish() kept its checkpoint):
// continued only with a larger limit, which is what makes it go further (checked before
// the fields are read: at 8192² they are a gigabyte).
void check_stopped_limit(const fs::path& dir, const fs::path& partial, const Case& c, const std::string& file) {
  std::string stopped;
  if (is_root() && fs::exists(partial / "stopped.toml")) {
    std::ifstream in(partial / "stopped.toml");
    std::stringstream text;
    text << in.rdbuf();
    stopped = text.str();
  }
  broadcast(stopped);
  if (stopped.empty()) return;
  toml::table st;
  try {
    st = toml::parse(stopped, (partial / "stopped.toml").string());
  } catch (const toml::parse_error&) {
  }
  const auto* lim = st["max_outer_steps"].as_integer();
  if (!lim) throw damaged(file, ".partial/stopped.toml: expected max_outer_steps = N");
  const long long was = lim->get();
  const std::string why = dir.string() + ": this run stopped at solver.max_outer_steps = " + std::to_string(was) +
                          " before its tolerance (step " + std::to_string(st["step"].value_or(0LL)) +
                          ", summary.json); ";
  const std::string how = "to continue it, resume with a larger limit, e.g. --set solver.max_outer_steps=" +
                          std::to_string(2 * was) + " (and the --set options it was run with)";
  // The same limit: a rerun would stop where it did, with the same bits; nothing changes.
  if (c.solver.max_outer_steps == was) throw RunStopped(why + "left as it is; " + how);
  if (c.solver.max_outer_steps < was)
    throw CaseError(why + "a smaller limit cannot continue it; " + how + ", or run without --resume to start afresh");
}

// One finished step of the checkpoint's 'steps', as Writer::step_json wrote it.
StepRecord step_from(const toml::table& r, const std::string& file) {
  StepRecord rec;
  rec.index = int(r["index"].value_or(0));
  rec.branch = records::branch_named(r["branch"].value_or(std::string("loading")), file);
  rec.mean_pressure = r["mean_pressure"].value_or(0.0);
  rec.force = r["force"].value_or(0.0);
  rec.penetration = r["penetration"].value_or(0.0);
  rec.mean_gap = r["mean_gap"].value_or(0.0);
  rec.contact_fraction = r["contact_fraction"].value_or(0.0);
  rec.energy = r["energy"].value_or(0.0);
  rec.result.iterations = int(r["iterations"].value_or(0));
  rec.result.converged = r["converged"].value_or(false);
  rec.result.residual = r["residual"].value_or(0.0);
  rec.result.wall_s = r["wall_s"].value_or(0.0);
  rec.result.fft_pairs = r["fft_pairs"].value_or(0.0);
  rec.result.fft_s = r["fft_s"].value_or(0.0);
  rec.result.message = r["message"].value_or(std::string());
  rec.result.diagnostics = records::diagnostics_from(r["diagnostics"]);
  rec.jump = r["jump"].value_or(false);
  rec.halvings = int(r["halvings"].value_or(0));
  if (auto* o = r["observables"].as_table()) {
    ObservablesRecord so;
    for (const auto& [k, v] : *o) so.scalars.emplace_back(std::string(k.str()), v.value_or(0.0));
    rec.observables = so;
  }
  return rec;
}

// The state to go on from (reduced units, bit for bit).
void read_state(const toml::table& t, hid_t f, const Grid& n, ContactState& state, const std::string& file) {
  const auto* st = t["state"].as_table();
  const auto* pen = st ? (*st)["penetration"].as_floating_point() : nullptr;
  const auto* mp = st ? (*st)["mean_pressure"].as_floating_point() : nullptr;
  if (!pen || !mp) throw damaged(file, "key 'state': expected {penetration, mean_pressure}");
  // A checkpoint inside a step leaves the state out (the step's solve goes on from `inside`).
  if ((*st)["fields"].value_or(true)) {
    if (!h5::read_fields(f, "state", n, state_fields(state)))
      throw damaged(file, "group 'state': expected the fields on this grid");
    state.penetration = pen->get();
    state.mean_pressure = mp->get();
  }
}

// Where a quasi-static step's solve stood inside the step after `done` of `steps` steps.
OuterPoint read_inside(const toml::table& in, hid_t f, const Grid& n, std::size_t done, std::size_t steps,
                       const std::string& file) {
  OuterPoint at;
  const auto* outer = in["outer"].as_integer();
  const auto* ipen = in["penetration"].as_floating_point();
  if (!outer || outer->get() < 1 || !ipen) throw damaged(file, "key 'inside': expected {outer >= 1, penetration, ...}");
  if (done >= steps) throw damaged(file, "key 'inside': a step inside a run whose steps are all done");
  at.outer = int(outer->get());
  at.inner.penetration = ipen->get();
  at.so_far.iterations = int(in["iterations"].value_or(0));
  at.so_far.fft_pairs = in["fft_pairs"].value_or(0.0);
  at.so_far.wall_s = in["wall_s"].value_or(0.0);
  at.so_far.fft_s = in["fft_s"].value_or(0.0);
  at.so_far.diagnostics = records::diagnostics_from(in["diagnostics"]);
  if (!h5::read_fields(f, "inside", n, inside_fields(at)))
    throw damaged(file, "group 'inside': expected the fields on this grid");
  return at;
}

// A changed stopping limit continues the path a fresh run with it takes only if no solve
// has reached it yet (CaseDiff.hpp): every finished step converged within it, and the step
// under way has made fewer outer steps than it. (The other solvers do not read
// solver.max_outer_steps: for them a change changes nothing.)
void check_changed_limit(const Case& c, const RunPoint& resume, const fs::path& dir) {
  const int limit = c.solver.max_outer_steps;
  auto refuse = [&](const std::string& why) {
    return CaseError(dir.string() + ": solver.max_outer_steps = " + std::to_string(limit) + " cannot continue this run (" +
                     why + "): a fresh run with that limit would have stopped elsewhere; resume with a larger value");
  };
  for (const auto& rec : resume.done) {
    if (!rec.result.converged)
      throw refuse("step " + std::to_string(rec.index) + " stopped unconverged under the checkpoint's limit");
    if (rec.result.diagnostics.outer_iterations > limit)
      throw refuse("step " + std::to_string(rec.index) + " took " +
                   std::to_string(rec.result.diagnostics.outer_iterations) + " outer steps");
  }
  if (resume.inside && resume.inside->outer >= limit)
    throw refuse("the step under way has made " + std::to_string(resume.inside->outer) + " outer steps");
}

// The load path's walk (key 'path'), with its pull-off state's fields (group 'pulloff').
void read_path(const toml::table& path, hid_t f, const Grid& n, RunPoint& resume, const std::string& file) {
  resume.path = path_from(path, file);
  const double pp = resume.path.pulloff_state.penetration, pm = resume.path.pulloff_state.mean_pressure;
  if (path["pulloff_state"].value_or(false)) {
    if (!h5::read_fields(f, "pulloff", n, state_fields(resume.path.pulloff_state)))
      throw damaged(file, "group 'pulloff': expected the fields on this grid");
    resume.path.pulloff_state.penetration = pp;
    resume.path.pulloff_state.mean_pressure = pm;
  } else {
    resume.path.pulloff_state = ContactState{};
  }
  if (resume.path.next != resume.done.size()) throw damaged(file, "key 'path.next': expected the number of steps");
}

}  // namespace

void Writer::load_partial() {
  const std::string file = checkpoint_.string();
  H5Handle f;
  const toml::table t = read_progress(checkpoint_, f);
  const CaseDiff diff = compare_cases(t["case"].value_or(std::string()), to_json(case_.resolved));
  if (!diff.same())
    throw CaseError(dir_.string() + " holds a partial run of a different case (or other --set values; first difference: " +
                    diff.mismatch + "): run without --resume to start afresh, or use another --out");
  check_stopped_limit(dir_, partial_, case_, file);
  auto notice = [&](const std::string& what) {
    notice_ += (notice_.empty() ? "" : "\n") + ("the checkpoint in " + dir_.string() + " ") + what;
  };
  for (const auto& key : diff.text_changed) notice("has another " + key + " (free text; the run goes on with this one)");
  for (const auto& key : diff.defaulted)
    notice("predates the key " + key + ", which holds its default here: the run it continues used that");
  if (auto* steps = t["steps"].as_array())
    for (auto& node : *steps) {
      const toml::table* rt = node.as_table();
      if (!rt) throw damaged(file, "key 'steps': expected tables");
      records_.push_back(*rt);
      const StepRecord rec = step_from(*rt, file);
      if (rec.index != int(resume_.done.size())) throw damaged(file, "key 'steps': step indices out of order");
      resume_.done.push_back(rec);
    }
  read_state(t, f, scene_.grid, resume_.state, file);
  if (const auto* sf = t["start_from"].as_table()) start_ = *sf;
  if (const auto* in = t["inside"].as_table())
    resume_.inside = read_inside(*in, f, scene_.grid, resume_.done.size(), scene_.targets.size(), file);
  if (!diff.limits_changed.empty() && case_.solver.kind == SolverKind::QuasiStatic)
    check_changed_limit(case_, resume_, dir_);
  for (const auto& what : diff.limits_changed)
    notice("has another stopping limit, " + what + " (the run continues its path and stops at the new limit)");
  if (const auto* path = t["path"].as_table()) read_path(*path, f, scene_.grid, resume_, file);
  if (writes_step_files()) {
    std::string missing;
    if (is_root())
      for (const StepRecord& r : resume_.done)
        if (missing.empty())
          missing = step_file_problem(step_file(r.index), r.index, scene_.grid.nx, scene_.grid.ny, case_.write_fields);
    broadcast(missing);
    if (!missing.empty()) throw CaseError(missing + ": the partial run cannot be finished; run without --resume");
  }
}

void Writer::checkpoint(const ContactState& st, const PathState* path, const OuterPoint* inside) {
  // Everything in one file, renamed over the last checkpoint: a run interrupted at any
  // moment is continued from the last complete one. Inside a step, the step's solve
  // (`inside`) replaces the state it started from.
  if (stopped_step_ >= 0) return;  // kept for a larger limit (add_step)
  if (inside && inside->fetch) inside->fetch();  // the solve's fields live on the GPU
  const bool with_state = !inside && !st.empty();
  auto fields = [&](hid_t f) {
    if (with_state) h5::write_fields(f, "state", scene_.grid, state_fields(st));
    if (inside) h5::write_fields(f, "inside", scene_.grid, inside_fields(*inside));
    if (path && !path->pulloff_state.empty())
      h5::write_fields(f, "pulloff", scene_.grid, state_fields(path->pulloff_state));
  };
  if (!is_root()) {  // the fields' slabs go to rank 0
    fields(-1);
    return;
  }
  write_output_file(checkpoint_, [&](const fs::path& tmp) {
    H5Handle f(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
    if (!f.ok()) throw std::runtime_error(tmp.string() + ": cannot write the checkpoint");
    toml::table t{{"format", 1},
                  {"case", to_json(case_.resolved)},
                  {"steps", records_},
                  {"state", toml::table{{"penetration", st.penetration},
                                        {"mean_pressure", st.mean_pressure},
                                        {"fields", with_state}}}};
    if (path) t.insert("path", path_table(*path));
    if (!start_.empty()) t.insert("start_from", start_);
    if (inside)
      t.insert("inside", toml::table{{"outer", inside->outer},
                                     {"penetration", inside->inner.penetration},
                                     {"iterations", inside->so_far.iterations},
                                     {"fft_pairs", inside->so_far.fft_pairs},
                                     {"wall_s", inside->so_far.wall_s},
                                     {"fft_s", inside->so_far.fft_s},
                                     {"diagnostics", records::diagnostics_table(inside->so_far.diagnostics)}});
    std::ostringstream p;
    p << t << "\n";
    h5::text_dataset(f, "progress", p.str());
    fields(f);
    h5::check(f.reset(), "closing the checkpoint " + tmp.string());
  });
}

}  // namespace cmc
