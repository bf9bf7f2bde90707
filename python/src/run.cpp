// Cases and runs from Python: a case file read and checked by the input layer (the same
// messages as `cmc run`), and a run of it by the driver `cmc run` uses (the same numbers,
// bit for bit), kept in memory, or written into a folder as `cmc run --out` writes it.
#include "arrays.hpp"
#include "bindings.hpp"

#include "cmc/grid/Ranks.hpp"
#include "cmc/output/Writer.hpp"
#include "cmc/run/Driver.hpp"
#include "cmc/scene/Scene.hpp"

#include <pybind11/stl.h>

#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

namespace cmcpy {

namespace {

toml::array to_array(const py::handle& v, const std::string& what);

// A Python value as a TOML value handed to `put`: bool, int, float, str, or a list or
// tuple of them (the package turns numpy scalars into these first).
template <class Put>
void put_value(const py::handle& v, const std::string& what, Put&& put) {
  if (py::isinstance<py::bool_>(v)) put(v.cast<bool>());
  else if (py::isinstance<py::int_>(v)) put(v.cast<long long>());
  else if (py::isinstance<py::float_>(v)) put(v.cast<double>());
  else if (py::isinstance<py::str>(v)) put(v.cast<std::string>());
  else if (py::isinstance<py::list>(v) || py::isinstance<py::tuple>(v)) put(to_array(v, what));
  else
    throw cmc::CaseError(what + ": expected a bool, number, string or list, got " +
                         std::string(py::str(py::type::of(v).attr("__name__"))));
}

toml::array to_array(const py::handle& v, const std::string& what) {
  toml::array a;
  for (const py::handle& e : v) put_value(e, what, [&](auto&& x) { a.push_back(std::forward<decltype(x)>(x)); });
  return a;
}

// {"grid": {"n": 64, ...}, ...} as a case table.
toml::table case_table(const py::dict& sections, const std::string& label) {
  toml::table t;
  for (const auto& [name, keys] : sections) {
    const std::string section = py::str(name);
    toml::table s;
    for (const auto& [k, v] : keys.cast<py::dict>()) {
      const std::string key = py::str(k);
      put_value(v, label + ": [" + section + "] " + key,
                [&](auto&& x) { s.insert_or_assign(key, std::forward<decltype(x)>(x)); });
    }
    t.insert_or_assign(section, std::move(s));
  }
  return t;
}

// The fields of a solved step in SI (pressure in Pa, displacement and gap in m).
struct StepFields {
  cmc::Field pressure, displacement, gap;
};

struct RunOutput {
  std::string summary_json;
  cmc::Field heights;  // m
  int nx = 0, ny = 0;
  std::vector<StepFields> fields;
  std::vector<std::map<std::string, cmc::ObservablesRecord::Array>> observables;
};

// What summary.json says of a run, for a run kept in memory: the same records of the
// case, the grid, the surface, the steps (Writer::step_json) and the run's status and cost.
toml::table summary_table(const cmc::Case& c, const cmc::Scene& s, const cmc::RunSummary& run) {
  const cmc::Units& u = s.units;
  const cmc::Grid& g = s.grid;
  toml::table t{{"cmc_version", CMC_VERSION},
                {"case_file", c.file},
                {"case", c.resolved},
                {"units", toml::table{{"length", "m"}, {"pressure", "Pa"}, {"force", "N"}, {"energy", "J"}}},
                {"grid", toml::table{{"nx", g.nx}, {"ny", g.ny}, {"size_x", u.to_m(g.lx)}, {"size_y", u.to_m(g.ly)},
                                     {"dx", u.to_m(g.dx())}, {"dy", u.to_m(g.dy())},
                                     {"boundary", s.half_space->periodic() ? "periodic" : "free"},
                                     {"threads", cmc::thread_count()}, {"backend", c.grid.backend}}},
                {"surface", s.topography.description},
                {"status", cmc::status_name(run.status)},
                {"message", run.message}};
  toml::table facts;
  for (const auto& [k, v] : cmc::surface_fact_entries(s.surface_facts)) facts.insert(k, v);
  t.insert("surface_facts", facts);
  toml::array warnings, steps;
  for (const auto& w : s.warnings) warnings.push_back(w);
  for (const auto& r : run.steps) steps.push_back(cmc::Writer::step_json(r));
  t.insert("warnings", warnings);
  t.insert("timing", toml::table{{"wall_s", run.wall_s}, {"fft_pairs", run.fft_pairs},
                                 {"iterations", run.iterations}, {"fft_pair_s", run.fft_pair_s}});
  t.insert("steps", steps);
  if (run.load_path)
    t.insert("load_path", toml::table{{"pulloff_mean_pressure", run.pulloff_mean_pressure},
                                      {"pulloff_force", run.pulloff_force},
                                      {"halved_steps", run.halved_steps},
                                      {"jumps", run.jumps}});
  return t;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  if (!in) throw std::runtime_error(path + ": cannot read what the run wrote");
  return s.str();
}

// Solve `c` (on `heights`, metres, in place of its surface, when given) with the
// driver of `cmc run`; into `out` as `cmc run --out` writes it when `out` is not empty.
// Runs without the GIL; `progress` takes it to look for Ctrl-C and to call back.
RunOutput run_case(const cmc::Case& c, const std::optional<std::span<const double>>& heights,
                   const std::string& out, PythonProgress& progress) {
  cmc::Scene scene = heights ? cmc::build_scene(c, *heights) : cmc::build_scene(c);
  RunOutput o;
  o.nx = scene.grid.nx, o.ny = scene.grid.ny;
  const cmc::Units& u = scene.units;
  auto keep = [&](const cmc::StepRecord& r, const cmc::ContactState& st) {
    progress.step = r.index + 1;
    if (r.observables) o.observables.push_back(r.observables->arrays);
    if (!c.write_fields) return;
    o.fields.push_back({scaled(st.pressure, u.pressure_pa), scaled(st.displacement, u.length_m),
                        scaled(st.gap, u.length_m)});
  };
  if (out.empty()) {
    const cmc::RunSummary run = cmc::run_scene(c, scene, keep, progress.hook());
    o.summary_json = cmc::to_json(summary_table(c, scene, run));
  } else {
    cmc::Writer writer(out, c, scene, false);
    try {
      const cmc::RunSummary run = cmc::run_scene(
          c, scene,
          [&](const cmc::StepRecord& r, const cmc::ContactState& st) {
            writer.add_step(r, st);
            keep(r, st);
          },
          progress.hook(), nullptr,
          [&](const cmc::ContactState& st, const cmc::PathState* path, const cmc::OuterPoint* inside) {
            // Between steps, and before a solve's last allowed outer step (a larger
            // limit continues from there: `cmc run --resume`, Writer.hpp).
            if (!inside || inside->outer + 1 >= c.solver.max_outer_steps) writer.checkpoint(st, path, inside);
          });
      writer.finish(run);
    } catch (const py::error_already_set&) {  // its text (a traceback) needs the GIL, and says less
      writer.fail("stopped from Python: Ctrl-C, or an exception raised by the progress callback");
      throw;
    } catch (const std::exception& e) {
      writer.fail(e.what());
      throw;
    }
    o.summary_json = read_text((writer.dir() / "summary.json").string());
  }
  o.heights = std::move(scene.topography.heights);  // the scene ends here: its buffer, in metres
  scale_in_place(o.heights, u.length_m);
  return o;
}

// The run's output as Python objects: the summary as JSON text (json.loads in the package)
// and numpy arrays over the fields and observables (no copy).
py::dict to_python(RunOutput&& o) {
  py::dict d;
  d["summary_json"] = o.summary_json;
  d["heights"] = adopt_field(std::move(o.heights), o.nx, o.ny);
  py::list fields, observables;
  for (StepFields& f : o.fields) {
    py::dict step;
    step["pressure"] = adopt_field(std::move(f.pressure), o.nx, o.ny);
    step["displacement"] = adopt_field(std::move(f.displacement), o.nx, o.ny);
    step["gap"] = adopt_field(std::move(f.gap), o.nx, o.ny);
    fields.append(step);
  }
  for (auto& step : o.observables) {
    py::dict arrays;
    for (auto& [name, a] : step) {
      const py::ssize_t n = py::ssize_t(a.values.size());
      arrays[py::str(name)] = py::make_tuple(adopt(std::move(a.values), {n}), a.unit);
    }
    observables.append(arrays);
  }
  d["fields"] = fields;
  d["observables"] = observables;
  return d;
}

using Heights = py::array_t<double, py::array::c_style | py::array::forcecast>;

py::dict run(const cmc::Case& c, const std::optional<Heights>& heights, const std::string& out,
             const py::object& callback) {
  PythonProgress progress{callback};
  std::optional<std::span<const double>> h;
  if (heights) h = values_of(*heights);
  RunOutput o;
  {
    py::gil_scoped_release free;
    o = run_case(c, h, out, progress);
  }
  return to_python(std::move(o));
}

}  // namespace

void bind_run(py::module_& m) {
  py::class_<cmc::Case, std::shared_ptr<cmc::Case>>(m, "Case", "A case, read and checked (cmc.Case wraps it).")
      .def_readonly("file", &cmc::Case::file)
      .def_readonly("name", &cmc::Case::name)
      .def_readonly("description", &cmc::Case::description)
      .def_property_readonly("nx", [](const cmc::Case& c) { return c.grid.nx; })
      .def_property_readonly("ny", [](const cmc::Case& c) { return c.grid.ny; })
      .def_readonly("write_fields", &cmc::Case::write_fields)
      .def("resolved_json", [](const cmc::Case& c) { return cmc::to_json(c.resolved); },
           "The case as run (defaults filled in, overrides applied), as JSON text.");
  m.def(
      "load_case",
      [](const std::string& path, const std::vector<std::string>& overrides) {
        return std::make_shared<cmc::Case>(cmc::load_case(path, overrides));
      },
      py::arg("path"), py::arg("overrides"),
      "Read and check a case file with `--set`-style overrides (\"section.key=value\").");
  m.def(
      "case_from_sections",
      [](const py::dict& sections, const std::string& label) {
        return std::make_shared<cmc::Case>(cmc::parse_case(case_table(sections, label), label));
      },
      py::arg("sections"), py::arg("label"),
      "Check a case given as {section: {key: value}}; `label` stands for the file in messages.");
  m.def("run", &run, py::arg("case"), py::arg("heights"), py::arg("out"), py::arg("progress"),
        "Run a case (on `heights`, metres, in place of its surface, when given); write into `out` "
        "unless it is empty. Returns the summary as JSON and the arrays.");
}

}  // namespace cmcpy
