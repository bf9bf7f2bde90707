#include "cmc/output/Writer.hpp"

#include "cmc/surface/H5Handle.hpp"

#include <hdf5.h>
#include <unistd.h>

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <utility>

namespace cmc {

namespace fs = std::filesystem;

void write_atomically(const fs::path& path, const std::string& text) {
  const fs::path tmp = path.parent_path() / ("." + path.filename().string() + ".tmp" + std::to_string(::getpid()));
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error(tmp.string() + ": cannot write (is the output folder writable?)");
    out << text;
    out.flush();
    if (!out) throw std::runtime_error(tmp.string() + ": write failed (disk full?)");
  }
  fs::rename(tmp, path);
}

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
// A (ny, nx) dataset of `values` times `scale`, with its unit.
void dataset(hid_t where, const std::string& name, const Grid& g, const Field& values, double scale, const char* unit,
             const char* meaning) {
  hsize_t dims[2] = {hsize_t(g.ny), hsize_t(g.nx)};
  H5Handle space(H5Screate_simple(2, dims, nullptr), H5Sclose);
  H5Handle d(H5Dcreate2(where, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
             H5Dclose);
  check(d, "dataset " + name);
  Field scaled(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) scaled[i] = values[i] * scale;
  check(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, scaled.data()), "writing " + name);
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
}  // namespace

Writer::Writer(fs::path dir, const Case& c, const Scene& s, bool resume) : dir_(std::move(dir)), case_(c), scene_(s) {
  std::error_code ec;
  fs::create_directories(dir_, ec);
  if (ec || !fs::is_directory(dir_)) throw std::runtime_error(dir_.string() + ": cannot create the output folder");
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  progress_ = dir_ / ".progress.toml";
  checkpoint_ = dir_ / ".checkpoint.h5";
  h5_tmp_ = dir_ / ".result.h5.partial";
  if (resume && fs::exists(progress_)) {
    load_partial();
    if (!resume_.done.empty()) return;
  }
  for (const auto& f : {progress_, checkpoint_, h5_tmp_}) fs::remove(f, ec);
  if (!c.write_fields) {
    h5_tmp_.clear();
    return;
  }
  // The file stays in a handle until its root is written: if a write throws, the
  // constructor does not complete, ~Writer does not run, and the handle closes it.
  H5Handle file(H5Fcreate(h5_tmp_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
  if (!file.ok()) throw std::runtime_error(h5_tmp_.string() + ": cannot create the HDF5 file");
  const Units& u = s.units;
  const Grid& g = s.grid;
  const hid_t root = file;
  attr_string(root, "case", c.name);
  attr_string(root, "cmc_version", CMC_VERSION);
  attr_double(root, "dx", u.to_m(g.dx()));
  attr_double(root, "dy", u.to_m(g.dy()));
  attr_double(root, "size_x", u.to_m(g.lx));
  attr_double(root, "size_y", u.to_m(g.ly));
  attr_string(root, "length_units", "m");
  dataset(root, "heights", g, s.topography.heights, u.length_m, "m", "indenter heights h (gap g = h - penetration + u)");
  file_ = file.release();  // from here on ~Writer closes it
}

void Writer::load_partial() {
  toml::table t;
  try {
    t = toml::parse_file(progress_.string());
  } catch (const toml::parse_error&) {
    throw CaseError(progress_.string() + ": unreadable progress file of a partial run; remove it or run without --resume");
  }
  if (t["case"].value_or(std::string()) != to_json(case_.resolved))
    throw CaseError(dir_.string() + " holds a partial run of a different case (or other --set values): run without "
                    "--resume to start afresh, or use another --out");
  const Units& u = scene_.units;
  if (auto* steps = t["steps"].as_array())
    for (auto& node : *steps) {
      const toml::table& r = *node.as_table();
      records_.push_back(r);
      StepRecord rec;
      rec.index = int(r["index"].value_or(0));
      rec.branch = branch_named(r["branch"].value_or(std::string("loading")), progress_.string());
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
      rec.result.message = r["message"].value_or(std::string());
      SolveDiagnostics& d = rec.result.diagnostics;
      const auto diag = r["diagnostics"];
      d.restarts = int(diag["restarts"].value_or(0));
      d.backtracks = int(diag["backtracks"].value_or(0));
      d.negative_curvature = int(diag["negative_curvature"].value_or(0));
      d.clipped_steps = int(diag["clipped_steps"].value_or(0));
      d.exact_recomputes = int(diag["exact_recomputes"].value_or(0));
      d.outer_iterations = int(diag["outer_iterations"].value_or(0));
      rec.jump = r["jump"].value_or(false);
      rec.halvings = int(r["halvings"].value_or(0));
      if (auto* o = r["observables"].as_table()) {
        ObservablesRecord so;
        for (const auto& [k, v] : *o) so.scalars.emplace_back(std::string(k.str()), v.value_or(0.0));
        rec.observables = so;
      }
      resume_.done.push_back(rec);
    }
  // The warm start: the last finished step's fields (reduced units).
  {
    H5Handle f(H5Fopen(checkpoint_.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
    if (!f.ok()) throw CaseError(checkpoint_.string() + ": missing checkpoint of a partial run; run without --resume");
    const std::size_t n = scene_.grid.size();
    for (auto [name, field] : {std::pair{"pressure", &resume_.state.pressure},
                               {"displacement", &resume_.state.displacement}, {"gap", &resume_.state.gap}}) {
      field->resize(n);
      H5Handle d(H5Dopen2(f, name, H5P_DEFAULT), H5Dclose);
      if (!d.ok() || H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, field->data()) < 0)
        throw CaseError(checkpoint_.string() + ": unreadable checkpoint; run without --resume");
    }
  }
  resume_.state.penetration = u.length(resume_.done.back().penetration);
  resume_.state.mean_pressure = u.pressure(resume_.done.back().mean_pressure);
  steps_written_ = int(resume_.done.size());
  if (case_.write_fields) {
    file_ = H5Fopen(h5_tmp_.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    if (file_ < 0) throw CaseError(h5_tmp_.string() + ": missing partial result file; run without --resume");
  } else {
    h5_tmp_.clear();
  }
}

Writer::~Writer() {
  if (file_ >= 0) H5Fclose(hid_t(file_));
}

void Writer::add_step(const StepRecord& rec, const ContactState& st) {
  // Checkpoint (reduced units, replaced atomically) and progress record, so that an
  // interrupted run can be resumed from here with --resume.
  {
    const fs::path tmp = dir_ / ".checkpoint.h5.tmp";
    H5Handle f(H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose);
    if (!f.ok()) throw std::runtime_error(tmp.string() + ": cannot write the checkpoint");
    dataset(f, "pressure", scene_.grid, st.pressure, 1.0, "E*", "reduced pressure");
    dataset(f, "displacement", scene_.grid, st.displacement, 1.0, "L", "reduced displacement");
    dataset(f, "gap", scene_.grid, st.gap, 1.0, "L", "reduced gap");
    check(f.reset(), "closing the checkpoint " + tmp.string());
    fs::rename(tmp, checkpoint_);
    records_.push_back(step_json(rec));
    std::ostringstream p;
    p << toml::table{{"case", to_json(case_.resolved)}, {"steps", records_}} << "\n";
    write_atomically(progress_, p.str());
  }
  if (file_ < 0) return;
  const Units& u = scene_.units;
  char name[32];
  std::snprintf(name, sizeof name, "step_%04d", rec.index);
  H5Handle grp(H5Gcreate2(hid_t(file_), name, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  check(grp, std::string("group ") + name);
  dataset(grp, "pressure", scene_.grid, st.pressure, u.pressure_pa, "Pa", "interfacial pressure, compressive > 0");
  dataset(grp, "displacement", scene_.grid, st.displacement, u.length_m, "m", "surface displacement into the solid");
  dataset(grp, "gap", scene_.grid, st.gap, u.length_m, "m", "interfacial gap g = h - penetration + u");
  attr_double(grp, "mean_pressure", rec.mean_pressure);
  attr_double(grp, "penetration", rec.penetration);
  attr_double(grp, "mean_gap", rec.mean_gap);
  attr_string(grp, "branch", branch_name(rec.branch));
  if (rec.observables) {
    H5Handle og(H5Gcreate2(grp, "observables", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    check(og, "group observables");
    for (const auto& [name, a] : rec.observables->arrays) vector_dataset(og, name, a.values, a.unit.c_str());
  }
  grp.reset();
  H5Fflush(hid_t(file_), H5F_SCOPE_LOCAL);
  ++steps_written_;
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
                     {"jump", r.jump},
                     {"halvings", r.halvings},
                     {"message", r.result.message}};
  const SolveDiagnostics& d = r.result.diagnostics;
  t.insert("diagnostics", toml::table{{"restarts", d.restarts},
                                      {"backtracks", d.backtracks},
                                      {"negative_curvature", d.negative_curvature},
                                      {"clipped_steps", d.clipped_steps},
                                      {"exact_recomputes", d.exact_recomputes},
                                      {"outer_iterations", d.outer_iterations}});
  if (r.observables) {
    toml::table o;
    for (const auto& [k, v] : r.observables->scalars) o.insert(k, v);
    t.insert("observables", o);
  }
  return t;
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
                           {"fft_size", (long long)scene_.half_space->transform_size()},
                           {"fft_plans", std::string(scene_.half_space->plan_source())}}},
      {"surface", scene_.topography.description},
  };
  toml::table facts;
  for (const auto& [k, v] : surface_fact_entries(scene_.surface_facts)) facts.insert(k, v);
  if (!facts.empty()) base.insert("surface_facts", facts);
  toml::array warnings;
  for (const auto& w : scene_.warnings) warnings.push_back(w);
  base.insert("warnings", warnings);
  return base;
}

void Writer::finish(const RunSummary& run, const toml::table& extra) {
  toml::table s = summary_base();
  s.insert("status", status_name(run.status));
  s.insert("message", run.message);
  s.insert("timing", toml::table{{"wall_s", run.wall_s},
                                 {"fft_pairs", run.fft_pairs},
                                 {"iterations", run.iterations},
                                 {"fft_pair_s", run.fft_pair_s},
                                 {"time_per_fft_pair", run.time_per_fft_pair},
                                 {"time_per_iteration", run.time_per_iteration}});
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
  if (file_ >= 0) {
    const hid_t f = hid_t(std::exchange(file_, -1));
    check(H5Fclose(f), "closing " + h5_tmp_.string());  // a failed close may leave it incomplete
    fs::rename(h5_tmp_, dir_ / "result.h5");
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
    write_atomically(dir_ / "result.xdmf", x.str());
  }
  write_atomically(dir_ / "summary.json", to_json(s));
  std::error_code ec;
  for (const auto& f : {progress_, checkpoint_}) fs::remove(f, ec);
}

void Writer::fail(const std::string& message) {
  // Results of an earlier run in the same folder must not pass for this run's.
  std::error_code ec;
  for (const char* f : {"result.h5", "result.xdmf"}) fs::remove(dir_ / f, ec);
  toml::table s = summary_base();
  s.insert("status", status_name(RunStatus::Failed));
  s.insert("message", message + (records_.empty() ? "" : " (the finished steps can be continued with --resume)"));
  write_atomically(dir_ / "summary.json", to_json(s));
}

}  // namespace cmc
