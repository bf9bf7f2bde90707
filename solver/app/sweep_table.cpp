// cmc sweep's table: each point's result read back from its summary.json, written as
// OUT/sweep.json (one record per point) and OUT/sweep.md (the same as a Markdown table).
#include "Sweep.hpp"

#include "cmc/output/Writer.hpp"

#include <cstdio>

namespace cmc::app {

namespace {

std::optional<double> number_at(const toml::node* n) {
  if (const auto v = n ? n->value<double>() : std::nullopt; v) return v;  // toml++ reads integers too
  return std::nullopt;
}

// "%.6g" of a value, "—" where there is none.
std::string cell(const std::optional<double>& v, const char* format = "%.6g") {
  if (!v) return "—";
  char text[40];
  std::snprintf(text, sizeof text, format, *v);
  return text;
}

}  // namespace

PointResult point_result(const toml::table& summary, const std::string& how) {
  PointResult r;
  r.how = how;
  r.status = summary["status"].value_or(std::string("failed"));
  r.message = summary["message"].value_or(std::string());
  r.nx = summary["grid"]["nx"].value_or(0LL);
  r.ny = summary["grid"]["ny"].value_or(0LL);
  const toml::array* steps = summary["steps"].as_array();
  if (!steps || steps->empty()) return r;
  for (const toml::node& s : *steps) {
    r.iterations += s.as_table() ? (*s.as_table())["iterations"].value_or(0LL) : 0LL;
    r.wall_s += s.as_table() ? (*s.as_table())["wall_s"].value_or(0.0) : 0.0;
  }
  const toml::table* last = steps->back().as_table();
  if (!last) return r;
  r.contact_fraction = number_at(last->get("contact_fraction"));
  r.mean_gap_m = number_at(last->get("mean_gap"));
  r.mean_pressure_pa = number_at(last->get("mean_pressure"));
  if (const auto* o = (*last)["observables"].as_table()) r.repulsive_fraction = number_at(o->get("repulsive_fraction"));
  return r;
}

namespace {

// The sweep's status: failed where a point failed, else not_run where one did not run
// (the sweep stopped), else not_converged where one did not converge, else converged.
std::string overall_status(const std::vector<PointResult>& results) {
  for (const char* s : {"failed", "not_run", "not_converged"})
    for (const PointResult& r : results)
      if (r.status == s) return s;
  return "converged";
}

toml::table point_record(const SweepPoint& p, const PointResult& r) {
  toml::table values;
  for (const auto& [key, value] : p.values) values.insert(key, value);
  toml::table t{{"values", values}, {"folder", p.folder}, {"status", r.status}, {"how", r.how}};
  if (p.grid > 0) t.insert("grid_n", p.grid);
  if (r.status == "not_run") return t;
  t.insert("grid", toml::array{r.nx, r.ny});
  t.insert("iterations", r.iterations);
  t.insert("wall_s", r.wall_s);
  t.insert("message", r.message);
  const std::pair<const char*, const std::optional<double>*> observed[] = {
      {"contact_fraction", &r.contact_fraction},
      {"repulsive_fraction", &r.repulsive_fraction},
      {"mean_gap_m", &r.mean_gap_m},
      {"mean_pressure_Pa", &r.mean_pressure_pa}};
  for (const auto& [key, v] : observed)
    if (*v) t.insert(key, **v);
  return t;
}

}  // namespace

std::string sweep_json(const SweepTable& t, const std::vector<SweepPoint>& points, const std::vector<PointResult>& results) {
  toml::table over;
  for (const SweepAxis& a : t.axes) {
    toml::array values;
    for (const auto& v : a.values) values.push_back(v);
    over.insert(a.key, values);
  }
  toml::array grids, sets, records;
  for (int n : t.grids) grids.push_back(n);
  for (const auto& s : t.sets) sets.push_back(s);
  for (std::size_t i = 0; i < points.size(); ++i) records.push_back(point_record(points[i], results[i]));
  return to_json(toml::table{{"cmc_version", CMC_VERSION},
                             {"case_file", t.case_file},
                             {"over", over},
                             {"grids", grids},
                             {"sets", sets},
                             {"folder_pattern", t.pattern},
                             {"status", overall_status(results)},
                             {"points", records}});
}

std::string sweep_markdown(const SweepTable& t, const std::vector<SweepPoint>& points,
                           const std::vector<PointResult>& results) {
  std::string md = "# Sweep: " + t.case_file + "\n\n";
  for (const auto& s : t.sets) md += (&s == &t.sets.front() ? "With --set " : ", ") + s;
  if (!t.sets.empty()) md += ".\n\n";
  md += "Last load step of each point, SI units; iterations and wall time (s) summed over the steps. "
        "status: " + overall_status(results) + ".\n\n|";
  for (const SweepAxis& a : t.axes) md += " " + a.key + " |";
  md += " grid | status | iterations | wall s | contact fraction | repulsive fraction | mean gap (m) | "
        "mean pressure (Pa) | folder |\n|";
  for (std::size_t k = 0; k < t.axes.size() + 9; ++k) md += "---|";
  md += "\n";
  for (std::size_t i = 0; i < points.size(); ++i) {
    const SweepPoint& p = points[i];
    const PointResult& r = results[i];
    md += "|";
    for (const auto& kv : p.values) md.append(" ").append(kv.second).append(" |");
    const std::string grid = r.nx ? std::to_string(r.nx) + " x " + std::to_string(r.ny)
                                  : p.grid ? std::to_string(p.grid) + "²" : "—";
    md.append(" ").append(grid).append(" | ").append(r.status).append(" | ");
    md.append(r.status == "not_run" ? "—" : std::to_string(r.iterations)).append(" | ");
    md.append(cell(r.status == "not_run" ? std::nullopt : std::optional(r.wall_s), "%.3g")).append(" | ");
    for (const auto* v : {&r.contact_fraction, &r.repulsive_fraction, &r.mean_gap_m, &r.mean_pressure_pa})
      md.append(cell(*v)).append(" | ");
    md.append(p.folder).append(" |\n");
  }
  return md;
}

}  // namespace cmc::app
