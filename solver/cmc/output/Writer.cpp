#include "cmc/output/Writer.hpp"

#include "cmc/grid/Backend.hpp"

#include "cmc/output/CaseDiff.hpp"
#include "cmc/output/RunFolder.hpp"

#include "cmc/grid/Ranks.hpp"
#include "cmc/surface/H5Handle.hpp"

#include <algorithm>
#include <hdf5.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <utility>

namespace cmc {

namespace fs = std::filesystem;

std::string to_json(const toml::table& t) {
  std::ostringstream s;
  s << toml::json_formatter{t} << "\n";
  return s.str();
}

namespace {
// Enum values as summary.json and result.h5 name them.
const char* branch_name(Branch b) { return b == Branch::Loading ? "loading" : "unloading"; }
Branch branch_named(const std::string& name, const std::string& file) {
  if (name == branch_name(Branch::Loading)) return Branch::Loading;
  if (name == branch_name(Branch::Unloading)) return Branch::Unloading;
  throw CaseError(file + ": step branch '" + name + "': expected \"loading\" or \"unloading\"; run without --resume");
}

void check(long long status, const std::string& what) {
  if (status < 0) throw std::runtime_error("HDF5: " + what + " failed");
}
// Every identifier below is held by an H5Handle (surface/H5Handle.hpp): a check() that
// throws closes whatever was opened before it.
void attr_string(hid_t obj, const char* name, const std::string& value) {
  H5Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, value.size() + 1);
  H5Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  H5Handle a(H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  check(a, std::string("attribute ") + name);
  check(H5Awrite(a, type, value.c_str()), std::string("attribute ") + name);
}
void attr_double(hid_t obj, const char* name, double value) {
  H5Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  H5Handle a(H5Acreate2(obj, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  check(a, std::string("attribute ") + name);
  check(H5Awrite(a, H5T_NATIVE_DOUBLE, &value), std::string("attribute ") + name);
}
// A (ny, nx) dataset of `values` times `scale`, with its unit. In a distributed run
// every rank calls it with its slab: rank 0 writes the rows of each rank in turn
// (holding one slab at a time; `where` is used on rank 0 only), the others send theirs.
void dataset(hid_t where, const std::string& name, const Grid& g, const Field& values, double scale, const char* unit,
             const char* meaning) {
  const hsize_t nx = hsize_t(g.nx);
  H5Handle space, d;
  if (is_root()) {
    hsize_t dims[2] = {hsize_t(g.ny), nx};
    space = H5Handle(H5Screate_simple(2, dims, nullptr), H5Sclose);
    d = H5Handle(H5Dcreate2(where, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                 H5Dclose);
    check(d, "dataset " + name);
  }
  // Scaled and written a block of rows at a time (about 2^20 values, 8 MB): a field is
  // never held twice on the host while it is written (a 32768² field is 8.6 GB).
  const std::size_t block_rows = std::max<std::size_t>(1, (std::size_t(1) << 20) / std::size_t(nx));
  Field scaled;
  for_each_slab(g, values.data(), [&](int y0, int rows, const double* v) {
    for (std::size_t r0 = 0; r0 < std::size_t(rows); r0 += block_rows) {
      const std::size_t rr = std::min(block_rows, std::size_t(rows) - r0), n = rr * nx;
      scaled.resize(n);
      const double* src = v + r0 * nx;
      for (std::size_t i = 0; i < n; ++i) scaled[i] = src[i] * scale;
      hsize_t start[2] = {hsize_t(y0) + hsize_t(r0), 0}, count[2] = {hsize_t(rr), nx};
      H5Handle mem(H5Screate_simple(2, count, nullptr), H5Sclose);
      check(H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr), "selecting rows of " + name);
      check(H5Dwrite(d, H5T_NATIVE_DOUBLE, mem, space, H5P_DEFAULT, scaled.data()), "writing " + name);
    }
  });
  if (!is_root()) return;
  attr_string(d, "units", unit);
  attr_string(d, "description", meaning);
}
void vector_dataset(hid_t where, const std::string& name, const std::vector<double>& v, const char* unit) {
  hsize_t dims[1] = {hsize_t(v.size())};
  H5Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose);
  H5Handle d(H5Dcreate2(where, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
             H5Dclose);
  check(d, "dataset " + name);
  if (!v.empty()) check(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "writing " + name);
  attr_string(d, "units", unit);
}
// A text as a scalar string dataset (no size limit, unlike an attribute).
void text_dataset(hid_t where, const char* name, const std::string& text) {
  H5Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, text.size() + 1);
  H5Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  H5Handle d(H5Dcreate2(where, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  check(d, std::string("dataset ") + name);
  check(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, text.c_str()), std::string("writing ") + name);
}
bool read_text(hid_t where, const char* name, std::string& text) {
  H5Handle d(H5Dopen2(where, name, H5P_DEFAULT), H5Dclose);
  if (!d.ok()) return false;
  H5Handle type(H5Dget_type(d), H5Tclose);
  if (!type.ok() || H5Tget_class(type) != H5T_STRING) return false;
  const std::size_t n = H5Tget_size(type);
  std::string buf(n, '\0');
  if (n == 0 || H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()) < 0) return false;
  text = buf.substr(0, buf.find('\0'));
  return true;
}
// Reduced fields of a checkpoint, exactly as the solver holds them: (name, field, unit).
// F is Field for reading into, const Field for writing from; one list of names serves both.
template <class F>
struct NamedField {
  const char* name;
  F* field;
  const char* unit;
};
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
// The (ny, nx) datasets of `group`, one per field.
void write_fields(hid_t where, const char* group, const Grid& g, const std::vector<NamedField<const Field>>& fields) {
  H5Handle grp;
  if (is_root()) {
    grp = H5Handle(H5Gcreate2(where, group, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    check(grp, std::string("group ") + group);
  }
  for (const auto& f : fields) dataset(grp, f.name, g, *f.field, 1.0, f.unit, "reduced value (checkpoint)");
}
// The (ny, nx) datasets of `group` into the fields, each rank its slab of grid g (rank 0
// reads blocks of rows and sends each rank its own). False (on every rank) if rank 0 finds
// one missing or of another shape.
bool read_fields(hid_t where, const char* group, const Grid& g, const std::vector<NamedField<Field>>& fields) {
  const std::size_t k = fields.size();
  H5Handle grp;
  std::vector<H5Handle> d(k), space(k);
  bool ok = true;
  if (is_root()) {
    grp = H5Handle(H5Gopen2(where, group, H5P_DEFAULT), H5Gclose);
    ok = grp.ok();
    for (std::size_t i = 0; ok && i < k; ++i) {
      d[i] = H5Handle(H5Dopen2(grp, fields[i].name, H5P_DEFAULT), H5Dclose);
      if (d[i].ok()) space[i] = H5Handle(H5Dget_space(d[i]), H5Sclose);
      hsize_t dims[2] = {0, 0};
      ok = d[i].ok() && space[i].ok() && H5Sget_simple_extent_ndims(space[i]) == 2 &&
           H5Sget_simple_extent_dims(space[i], dims, nullptr) == 2 && dims[0] == hsize_t(g.ny) && dims[1] == hsize_t(g.nx);
    }
  }
  if (!any_rank(ok)) return false;
  bool read_ok = true;
  for (std::size_t i = 0; i < k; ++i) {
    fields[i].field->resize(g.size());
    scatter_slabs(g, fields[i].field->data(), [&](int y0, int rows, double* v) {
      hsize_t start[2] = {hsize_t(y0), 0}, count[2] = {hsize_t(rows), hsize_t(g.nx)};
      H5Handle mem(H5Screate_simple(2, count, nullptr), H5Sclose);
      read_ok = read_ok && H5Sselect_hyperslab(space[i], H5S_SELECT_SET, start, nullptr, count, nullptr) >= 0;
      read_ok = read_ok && H5Dread(d[i], H5T_NATIVE_DOUBLE, mem, space[i], H5P_DEFAULT, v) >= 0;
    });
  }
  return !any_rank(!read_ok);
}

toml::table diagnostics_table(const SolveDiagnostics& d) {
  return toml::table{{"restarts", d.restarts},
                     {"backtracks", d.backtracks},
                     {"negative_curvature", d.negative_curvature},
                     {"clipped_steps", d.clipped_steps},
                     {"exact_recomputes", d.exact_recomputes},
                     {"outer_iterations", d.outer_iterations}};
}
SolveDiagnostics diagnostics_from(toml::node_view<const toml::node> t) {
  SolveDiagnostics d;
  d.restarts = int(t["restarts"].value_or(0));
  d.backtracks = int(t["backtracks"].value_or(0));
  d.negative_curvature = int(t["negative_curvature"].value_or(0));
  d.clipped_steps = int(t["clipped_steps"].value_or(0));
  d.exact_recomputes = int(t["exact_recomputes"].value_or(0));
  d.outer_iterations = int(t["outer_iterations"].value_or(0));
  return d;
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
    if constexpr (std::is_same_v<T, Branch>) t.insert(key, branch_name(v));
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
      v = branch_named(node.value_or(std::string()), file);
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

void Writer::load_partial() {
  const std::string file = checkpoint_.string();
  auto damaged = [&](const std::string& what) {
    return CaseError(file + ": " + what + " (a damaged checkpoint of a partial run); run without --resume to start afresh");
  };
  // Rank 0 reads the file; every rank parses the same text (a problem found on rank 0
  // travels as the text "!" plus the message, so that every rank stops alike).
  H5Handle f;
  std::string text;
  if (is_root()) {
    f = H5Handle(H5Fopen(checkpoint_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!f.ok()) text = "!not a readable HDF5 file";
    else if (!read_text(f, "progress", text)) text = "!no dataset 'progress'";
  }
  broadcast(text);
  if (!text.empty() && text[0] == '!') throw damaged(text.substr(1));
  toml::table t;
  try {
    t = toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    throw damaged("dataset 'progress' is not TOML (" + std::string(e.description()) + ")");
  }
  if (t["format"].value_or(0) != 1) throw damaged("key 'format': expected 1 (written by another version of cmc?)");
  const CaseDiff diff = compare_cases(t["case"].value_or(std::string()), to_json(case_.resolved));
  if (!diff.same())
    throw CaseError(dir_.string() + " holds a partial run of a different case (or other --set values; first difference: " +
                    diff.mismatch + "): run without --resume to start afresh, or use another --out");
  // A finished run that stopped at its outer-step limit (finish() kept its checkpoint):
  // continued only with a larger limit, which is what makes it go further (checked before
  // the fields are read: at 8192² they are a gigabyte).
  std::string stopped;
  if (is_root() && fs::exists(partial_ / "stopped.toml")) {
    std::ifstream in(partial_ / "stopped.toml");
    std::stringstream text;
    text << in.rdbuf();
    stopped = text.str();
  }
  broadcast(stopped);
  if (!stopped.empty()) {
    toml::table st;
    try {
      st = toml::parse(stopped, (partial_ / "stopped.toml").string());
    } catch (const toml::parse_error&) {
    }
    const auto* lim = st["max_outer_steps"].as_integer();
    if (!lim) throw damaged(".partial/stopped.toml: expected max_outer_steps = N");
    const long long was = lim->get();
    const std::string why = dir_.string() + ": this run stopped at solver.max_outer_steps = " + std::to_string(was) +
                            " before its tolerance (step " + std::to_string(st["step"].value_or(0LL)) +
                            ", summary.json); ";
    const std::string how = "to continue it, resume with a larger limit, e.g. --set solver.max_outer_steps=" +
                            std::to_string(2 * was) + " (and the --set options it was run with)";
    // The same limit: a rerun would stop where it did, with the same bits; nothing changes.
    if (case_.solver.max_outer_steps == was) throw RunStopped(why + "left as it is; " + how);
    if (case_.solver.max_outer_steps < was)
      throw CaseError(why + "a smaller limit cannot continue it; " + how + ", or run without --resume to start afresh");
  }
  auto notice = [&](const std::string& what) {
    notice_ += (notice_.empty() ? "" : "\n") + ("the checkpoint in " + dir_.string() + " ") + what;
  };
  for (const auto& key : diff.text_changed) notice("has another " + key + " (free text; the run goes on with this one)");
  for (const auto& key : diff.defaulted)
    notice("predates the key " + key + ", which holds its default here: the run it continues used that");
  if (auto* steps = t["steps"].as_array())
    for (auto& node : *steps) {
      const toml::table* rt = node.as_table();
      if (!rt) throw damaged("key 'steps': expected tables");
      const toml::table& r = *rt;
      records_.push_back(r);
      StepRecord rec;
      rec.index = int(r["index"].value_or(0));
      rec.branch = branch_named(r["branch"].value_or(std::string("loading")), file);
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
      rec.result.diagnostics = diagnostics_from(r["diagnostics"]);
      rec.jump = r["jump"].value_or(false);
      rec.halvings = int(r["halvings"].value_or(0));
      if (auto* o = r["observables"].as_table()) {
        ObservablesRecord so;
        for (const auto& [k, v] : *o) so.scalars.emplace_back(std::string(k.str()), v.value_or(0.0));
        rec.observables = so;
      }
      if (rec.index != int(resume_.done.size())) throw damaged("key 'steps': step indices out of order");
      resume_.done.push_back(rec);
    }
  // The state to go on from (reduced units, bit for bit).
  const Grid& n = scene_.grid;
  const auto* state = t["state"].as_table();
  const auto* pen = state ? (*state)["penetration"].as_floating_point() : nullptr;
  const auto* mp = state ? (*state)["mean_pressure"].as_floating_point() : nullptr;
  if (!pen || !mp) throw damaged("key 'state': expected {penetration, mean_pressure}");
  // A checkpoint inside a step leaves the state out (the step's solve goes on from `inside`).
  if ((*state)["fields"].value_or(true)) {
    if (!read_fields(f, "state", n, state_fields(resume_.state)))
      throw damaged("group 'state': expected the fields on this grid");
    resume_.state.penetration = pen->get();
    resume_.state.mean_pressure = mp->get();
  }
  if (const auto* sf = t["start_from"].as_table()) start_ = *sf;
  if (const auto* in = t["inside"].as_table()) {
    OuterPoint at;
    const auto* outer = (*in)["outer"].as_integer();
    const auto* ipen = (*in)["penetration"].as_floating_point();
    if (!outer || outer->get() < 1 || !ipen) throw damaged("key 'inside': expected {outer >= 1, penetration, ...}");
    if (resume_.done.size() >= scene_.targets.size())
      throw damaged("key 'inside': a step inside a run whose steps are all done");
    at.outer = int(outer->get());
    at.inner.penetration = ipen->get();
    at.so_far.iterations = int((*in)["iterations"].value_or(0));
    at.so_far.fft_pairs = (*in)["fft_pairs"].value_or(0.0);
    at.so_far.wall_s = (*in)["wall_s"].value_or(0.0);
    at.so_far.fft_s = (*in)["fft_s"].value_or(0.0);
    at.so_far.diagnostics = diagnostics_from((*in)["diagnostics"]);
    if (!read_fields(f, "inside", n, inside_fields(at)))
      throw damaged("group 'inside': expected the fields on this grid");
    resume_.inside = std::move(at);
  }
  if (!diff.limits_changed.empty() && case_.solver.kind == SolverKind::QuasiStatic) {
    // A changed stopping limit continues the path a fresh run with it takes only if no
    // solve has reached it yet (CaseDiff.hpp): every finished step converged within it,
    // and the step under way has made fewer outer steps than it. (The other solvers do
    // not read solver.max_outer_steps: for them a change changes nothing.)
    const int limit = case_.solver.max_outer_steps;
    auto refuse = [&](const std::string& why) {
      return CaseError(dir_.string() + ": solver.max_outer_steps = " + std::to_string(limit) + " cannot continue this run (" +
                       why + "): a fresh run with that limit would have stopped elsewhere; resume with a larger value");
    };
    for (const auto& rec : resume_.done) {
      if (!rec.result.converged)
        throw refuse("step " + std::to_string(rec.index) + " stopped unconverged under the checkpoint's limit");
      if (rec.result.diagnostics.outer_iterations > limit)
        throw refuse("step " + std::to_string(rec.index) + " took " +
                     std::to_string(rec.result.diagnostics.outer_iterations) + " outer steps");
    }
    if (resume_.inside && resume_.inside->outer >= limit)
      throw refuse("the step under way has made " + std::to_string(resume_.inside->outer) + " outer steps");
  }
  for (const auto& what : diff.limits_changed)
    notice("has another stopping limit, " + what + " (the run continues its path and stops at the new limit)");
  if (const auto* path = t["path"].as_table()) {
    resume_.path = path_from(*path, file);
    const double pp = resume_.path.pulloff_state.penetration, pm = resume_.path.pulloff_state.mean_pressure;
    if ((*path)["pulloff_state"].value_or(false)) {
      if (!read_fields(f, "pulloff", n, state_fields(resume_.path.pulloff_state)))
        throw damaged("group 'pulloff': expected the fields on this grid");
      resume_.path.pulloff_state.penetration = pp;
      resume_.path.pulloff_state.mean_pressure = pm;
    } else {
      resume_.path.pulloff_state = ContactState{};
    }
    if (resume_.path.next != resume_.done.size()) throw damaged("key 'path.next': expected the number of steps");
  }
  if (case_.write_fields) {
    std::string missing;
    if (is_root())
      for (const StepRecord& r : resume_.done)
        if (missing.empty()) missing = step_file_problem(step_file(r.index), r.index);
    broadcast(missing);
    if (!missing.empty()) throw CaseError(missing + ": the partial run cannot be finished; run without --resume");
  }
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
  if (case_.write_fields) {
    // The step's fields in a file of its own, written atomically: kept only when a
    // checkpoint names the step (a step redone after an interruption replaces it). In a
    // distributed run every rank sends rank 0 its slabs (`tmp` is rank 0's).
    const bool root = is_root();
    auto fill = [&](const fs::path& tmp) {
      H5Handle file, grp;
      const Units& u = scene_.units;
      char name[32];
      std::snprintf(name, sizeof name, "step_%04d", rec.index);
      if (root) {
        file = H5Handle(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
        if (!file.ok()) throw std::runtime_error(tmp.string() + ": cannot create the HDF5 file");
        grp = H5Handle(H5Gcreate2(file, name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
        check(grp, std::string("group ") + name);
      }
      dataset(grp, "pressure", scene_.grid, st.pressure, u.pressure_pa, "Pa", "interfacial pressure, compressive > 0");
      dataset(grp, "displacement", scene_.grid, st.displacement, u.length_m, "m", "surface displacement into the solid");
      dataset(grp, "gap", scene_.grid, st.gap, u.length_m, "m", "interfacial gap g = h - penetration + u");
      if (!root) return;
      attr_double(grp, "mean_pressure", rec.mean_pressure);
      attr_double(grp, "penetration", rec.penetration);
      attr_double(grp, "mean_gap", rec.mean_gap);
      attr_string(grp, "branch", branch_name(rec.branch));
      if (rec.observables) {
        H5Handle og(H5Gcreate2(grp, "observables", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
        check(og, "group observables");
        for (const auto& [oname, a] : rec.observables->arrays) vector_dataset(og, oname, a.values, a.unit.c_str());
      }
      grp.reset();
      check(file.reset(), "closing " + tmp.string());
    };
    if (root) write_output_file(step_file(rec.index), fill);
    else fill({});
  }
  records_.push_back(step_json(rec));
}

void Writer::checkpoint(const ContactState& st, const PathState* path, const OuterPoint* inside) {
  // Everything in one file, renamed over the last checkpoint: a run interrupted at any
  // moment is continued from the last complete one. Inside a step, the step's solve
  // (`inside`) replaces the state it started from.
  if (stopped_step_ >= 0) return;  // kept for a larger limit (add_step)
  if (inside && inside->fetch) inside->fetch();  // the solve's fields live on the GPU
  const bool with_state = !inside && !st.empty();
  auto fields = [&](hid_t f) {
    if (with_state) write_fields(f, "state", scene_.grid, state_fields(st));
    if (inside) write_fields(f, "inside", scene_.grid, inside_fields(*inside));
    if (path && !path->pulloff_state.empty())
      write_fields(f, "pulloff", scene_.grid, state_fields(path->pulloff_state));
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
                                     {"diagnostics", diagnostics_table(inside->so_far.diagnostics)}});
    std::ostringstream p;
    p << t << "\n";
    text_dataset(f, "progress", p.str());
    fields(f);
    check(f.reset(), "closing the checkpoint " + tmp.string());
  });
}

toml::table Writer::step_json(const StepRecord& r) {
  toml::table t{{"index", r.index},
                     {"branch", branch_name(r.branch)},
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
  t.insert("diagnostics", diagnostics_table(r.result.diagnostics));
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
  s.insert("timing", toml::table{{"wall_s", run.wall_s},
                                 {"fft_pairs", run.fft_pairs},
                                 {"iterations", run.iterations},
                                 {"fft_pair_s", run.fft_pair_s},
                                 {"time_per_fft_pair", run.time_per_fft_pair},
                                 {"time_per_iteration", run.time_per_iteration},
                                 {"row_column_pair_s", run.row_column_pair_s},
                                 {"floor_pair_s", run.floor_pair_s},
                                 {"time_per_floor_pair", run.time_per_floor_pair},
                                 {"fft_share", run.fft_share}});
  toml::array steps;
  for (const auto& r : run.steps) steps.push_back(step_json(r));
  s.insert("steps", steps);
  if (run.load_path)
    s.insert("load_path", toml::table{{"pulloff_mean_pressure", run.pulloff_mean_pressure},
                                      {"pulloff_force", run.pulloff_force},
                                      {"pulloff_branch", run.pulloff_branch ? branch_name(*run.pulloff_branch) : ""},
                                      {"halved_steps", run.halved_steps},
                                      {"jumps", run.jumps}});
  for (const auto& [k, v] : extra) s.insert_or_assign(k, v);
  if (!is_root()) {  // the heights' slabs go to rank 0, which writes everything
    if (case_.write_fields) dataset(-1, "heights", scene_.grid, scene_.topography.heights, 1.0, "", "");
    return;
  }
  if (case_.write_fields) {
    // result.h5: the heights, then every step's group copied from its file.
    write_output_file(dir_ / "result.h5", [&](const fs::path& tmp) {
      H5Handle file(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
      if (!file.ok()) throw std::runtime_error(tmp.string() + ": cannot create the HDF5 file");
      const Units& u = scene_.units;
      const Grid& g = scene_.grid;
      const hid_t root = file;
      attr_string(root, "case", case_.name);
      attr_string(root, "cmc_version", CMC_VERSION);
      attr_double(root, "dx", u.to_m(g.dx()));
      attr_double(root, "dy", u.to_m(g.dy()));
      attr_double(root, "size_x", u.to_m(g.lx));
      attr_double(root, "size_y", u.to_m(g.ly));
      attr_string(root, "length_units", "m");
      dataset(root, "heights", g, scene_.topography.heights, u.length_m, "m",
              "indenter heights h (gap g = h - penetration + u)");
      for (const auto& r : run.steps) {
        const fs::path from = step_file(r.index);
        H5Handle src(H5Fopen(from.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
        if (!src.ok()) throw std::runtime_error(from.string() + ": the fields of step " + std::to_string(r.index) +
                                                " are missing");
        char name[32];
        std::snprintf(name, sizeof name, "step_%04d", r.index);
        check(H5Ocopy(src, name, file, name, H5P_DEFAULT, H5P_DEFAULT), std::string("copying ") + name);
      }
      check(file.reset(), "closing " + tmp.string());  // a failed close may leave it incomplete
    });
    // XDMF pointer for ParaView: one 2-D uniform grid per step.
    const Grid& g = scene_.grid;
    const Units& u = scene_.units;
    std::ostringstream x;
    x << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
      << "<Grid Name=\"steps\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (const auto& r : run.steps) {
      char name[32];
      std::snprintf(name, sizeof name, "step_%04d", r.index);
      x << "<Grid Name=\"" << name << "\"><Time Value=\"" << r.index << "\"/>\n"
        << "<Topology TopologyType=\"2DCoRectMesh\" Dimensions=\"" << g.ny << " " << g.nx << "\"/>\n"
        << "<Geometry GeometryType=\"ORIGIN_DXDY\"><DataItem Dimensions=\"2\" Format=\"XML\">0 0</DataItem>"
        << "<DataItem Dimensions=\"2\" Format=\"XML\">" << u.to_m(g.dy()) << " " << u.to_m(g.dx())
        << "</DataItem></Geometry>\n";
      for (const char* f : {"pressure", "gap", "displacement"})
        x << "<Attribute Name=\"" << f << "\" Center=\"Node\"><DataItem Dimensions=\"" << g.ny << " " << g.nx
          << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">result.h5:/" << name << "/" << f
          << "</DataItem></Attribute>\n";
      x << "</Grid>\n";
    }
    x << "</Grid>\n</Domain>\n</Xdmf>\n";
    write_output_text(dir_ / "result.xdmf", x.str());
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
