#include "Refine.hpp"

#include "Validate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace cmc {

namespace {

std::optional<double> number(const toml::node* n) {
  if (!n) return std::nullopt;
  if (auto v = n->value<double>()) return *v;  // toml++ converts integers too
  return std::nullopt;
}

// The step's value of `key`: its "observables" entry first, then the step's own.
std::optional<double> step_value(const toml::table& step, const std::string& key) {
  if (const auto* o = step["observables"].as_table())
    if (auto v = number(o->get(key))) return v;
  return number(step.get(key));
}

std::vector<std::string> observable_keys(const std::vector<RefinementGrid>& grids) {
  std::vector<std::string> keys;
  auto add = [&](const std::string& k) {
    if (std::find(keys.begin(), keys.end(), k) == keys.end()) keys.push_back(k);
  };
  for (const auto& g : grids)
    if (const auto* o = g.last_step["observables"].as_table())
      for (const auto& [k, v] : *o)
        if (v.is_number()) add(std::string(k.str()));
  for (const char* k : {"penetration", "mean_gap", "contact_fraction", "iterations", "wall_s"}) add(k);
  return keys;
}

RefinementRow make_row(const std::string& key, const std::vector<RefinementGrid>& grids) {
  RefinementRow r{key, {}, {}, std::nullopt};
  for (const auto& g : grids) r.values.push_back(step_value(g.last_step, key));
  std::vector<int> at;
  std::vector<double> abs_changes;
  for (std::size_t k = 0; k + 1 < grids.size(); ++k) {
    const auto &a = r.values[k], &b = r.values[k + 1];
    r.changes.push_back(a && b && *b != 0.0 ? std::optional(std::abs(*b - *a) / std::abs(*b)) : std::nullopt);
    if (a && b && *b != *a) at.push_back(grids[k].n), abs_changes.push_back(std::abs(*b - *a));
  }
  if (at.size() >= 2 && at.size() + 1 == grids.size()) r.order = fit_order(at, abs_changes).order;
  return r;
}

std::string num(const std::optional<double>& v, const char* f = "%.6g") {
  if (!v) return "—";
  char buf[32];
  std::snprintf(buf, sizeof buf, f, *v);
  return buf;
}

toml::array optionals(const std::vector<std::optional<double>>& v) {
  toml::array a;
  for (const auto& x : v) x ? a.push_back(*x) : a.push_back(std::string("n/a"));
  return a;
}

}  // namespace

std::vector<RefinementRow> refinement_rows(const std::vector<RefinementGrid>& grids) {
  for (std::size_t k = 1; k < grids.size(); ++k)
    if (grids[k].n <= grids[k - 1].n) throw std::invalid_argument("refinement: grids must increase");
  std::vector<RefinementRow> rows;
  for (const auto& key : observable_keys(grids)) rows.push_back(make_row(key, grids));
  return rows;
}

std::string refinement_markdown(const std::string& case_file, const std::vector<RefinementGrid>& grids,
                                const std::vector<RefinementRow>& rows) {
  std::string md = "# Refinement study: " + case_file + "\n\n" +
                   "Last load step, SI units. change = |v_fine - v_coarse| / |v_fine| between successive grids; "
                   "the last change (two finest grids) is the estimated discretisation error of the finest. "
                   "order = observed order of the absolute changes (least-squares fit, validation/Validate.cpp "
                   "fit_order; needs three grids).\n\n| observable |";
  for (const auto& g : grids) md += " n = " + std::to_string(g.n) + " |";
  for (std::size_t k = 0; k + 1 < grids.size(); ++k)
    md += " change " + std::to_string(grids[k].n) + "→" + std::to_string(grids[k + 1].n) + " |";
  md += " order |\n|---|";
  for (std::size_t k = 0; k < 2 * grids.size(); ++k) md += "---|";
  md += "\n";
  for (const auto& r : rows) {
    md += "| " + r.observable + " |";
    // Appended piece by piece: `" " + num(...)` trips GCC 12's -Wrestrict false positive.
    for (const auto& v : r.values) md.append(" ").append(num(v)).append(" |");
    for (const auto& c : r.changes) md.append(" ").append(num(c, "%.2e")).append(" |");
    md.append(" ").append(num(r.order, "%.2f")).append(" |\n");
  }
  md += "\n| grid | dx (m) | dx / λ_s | modes dropped | status |\n|---|---|---|---|---|\n";
  for (const auto& g : grids)
    md += "| " + std::to_string(g.n) + "² | " + num(g.dx_m, "%.4g") + " | " +
          num(number(g.facts.get("dx_over_cutoff_wavelength")), "%.3g") + " | " +
          num(number(g.facts.get("modes_dropped")), "%.0f") + " | " + g.status + " |\n";
  return md;
}

toml::table refinement_record(const std::string& case_file, const std::vector<RefinementGrid>& grids,
                              const std::vector<RefinementRow>& rows) {
  toml::array gs, table, status;
  for (const auto& g : grids) {
    gs.push_back(g.n);
    status.push_back(toml::table{{"n", g.n}, {"status", g.status}, {"dx_m", g.dx_m}, {"facts", g.facts}});
  }
  for (const auto& r : rows) {
    toml::table t{{"observable", r.observable}, {"values", optionals(r.values)},
                  {"relative_changes", optionals(r.changes)}};
    if (r.order) t.insert("observed_order", *r.order);
    table.push_back(t);
  }
  return toml::table{{"case", case_file}, {"grids", gs}, {"runs", status}, {"rows", table}};
}

}  // namespace cmc
