// `cmc reference --run-curve SPEC.toml --out FILE.csv`: a reference curve made of a cmc
// run's numbers (the challenge curves, scripts/challenge_reference.py), written in the
// reference CSV format by validation/References.cpp (make_run_curve, write_curve), so
// there is one formatter of that format, in C++.
#include "commands.hpp"

#include "Check.hpp"
#include "References.hpp"

#include <cstdio>
#include <filesystem>

#include <toml++/toml.h>

namespace cmc::app {

namespace {

std::string need_string(const toml::table& t, const std::string& file, const std::string& key,
                        const std::string& where = "") {
  const auto v = t[key].value<std::string>();
  if (!v) throw CaseError(file + ": key '" + where + key + "': expected a string");
  return *v;
}

reference::Column column_from(const toml::node& node, const std::string& file, std::size_t k) {
  const std::string where = "columns[" + std::to_string(k) + "]";
  const auto* t = node.as_table();
  if (!t) throw CaseError(file + ": " + where + ": expected a table {name, unit, meaning, values}");
  reference::Column c{need_string(*t, file, "name", where + "."), need_string(*t, file, "unit", where + "."),
                      (*t)["meaning"].value_or(std::string()), {}};
  const auto* values = (*t)["values"].as_array();
  if (!values) throw CaseError(file + ": key '" + where + ".values': expected an array of numbers");
  for (const auto& v : *values) {
    const auto x = v.value<double>();
    if (!x) throw CaseError(file + ": key '" + where + ".values': expected numbers only");
    c.values.push_back(*x);
  }
  return c;
}

std::string g6(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

// A stored curve must be one that `cmc check` reads as a reference: the file is named after
// the curve (NAME.csv, as cmc check --quantity and cmc reference --check find curves), its
// text is read back as check reads a reference (x strictly monotonic, every value finite
// in SI), and its points are positive on the log axes of its representation.
void require_checkable(const reference::Curve& c, const std::string& text, const std::string& spec_file,
                       const std::string& out) {
  if (std::filesystem::path(out).filename() != c.name + ".csv")
    throw CaseError("--out " + out + ": expected a file named " + c.name + ".csv, after the curve's name (key 'name' of " +
                    spec_file + "), as stored curves are found by it");
  try {
    const reference::Table t = reference::parse_csv(text, spec_file, 2);
    const reference::Curve back = reference::curve_from_table(t);
    const reference::Representation rep = reference::parse_representation(back.representation);
    check::QuantitySpec spec = check::generic_spec(back.quantity, back.x, back.y, rep, 1.0, "max_abs");
    for (const auto& q : check::quantities())
      if (q.id == back.quantity) spec = q;
    const check::XY xy = check::extract(t, spec, back.band);
    for (std::size_t i = 0; i < xy.x.size(); ++i)
      if ((rep.log_x && !(xy.x[i] > 0)) || (rep.log_y && !(xy.y[i] > 0)))
        throw CaseError(spec_file + ": point " + std::to_string(i) + " (" + back.x + " = " + g6(xy.x[i]) +
                        ", " + back.y + " = " + g6(xy.y[i]) + ") is not positive on the log axes of the " +
                        back.representation + " representation: expected positive values there (cmc check would "
                        "leave the point out)");
  } catch (const reference::InputError& e) {
    throw CaseError(spec_file + ": the curve it would write is not one cmc check reads as a reference (lines of that curve): " + e.what());
  }
}

}  // namespace

int write_run_curve(const std::string& spec_file, const std::string& out) {
  if (out.empty()) throw CaseError("cmc reference --run-curve needs --out FILE.csv");
  toml::table t;
  try {
    t = toml::parse_file(spec_file);
  } catch (const toml::parse_error& e) {
    throw CaseError(spec_file + ": not a TOML curve spec (" + std::string(e.description()) + ")");
  }
  const auto* prov = t["provenance"].as_table();
  if (!prov) throw CaseError(spec_file + ": key 'provenance': expected a table");
  reference::RunProvenance how;
  for (auto [key, field] : {std::pair{"cmc_version", &how.cmc_version}, {"case_file", &how.case_file},
                            {"grid", &how.grid}, {"solver_tolerance", &how.solver_tolerance}, {"date", &how.date}})
    *field = need_string(*prov, spec_file, key);
  how.command = (*prov)["command"].value_or(std::string());
  const auto* cols = t["columns"].as_array();
  if (!cols || cols->size() < 2) throw CaseError(spec_file + ": key 'columns': expected an array of two or more tables");
  std::vector<reference::Column> columns;
  // (extra: optional; the other top-level keys are required strings, see --help)
  for (std::size_t k = 0; k < cols->size(); ++k) columns.push_back(column_from((*cols)[k], spec_file, k));
  reference::Curve c;
  try {
    c = reference::make_run_curve(need_string(t, spec_file, "name"), need_string(t, spec_file, "quantity"),
                                  t["title"].value_or(std::string()), how, std::move(columns),
                                  need_string(t, spec_file, "x"), need_string(t, spec_file, "y"),
                                  need_string(t, spec_file, "representation"),
                                  need_string(t, spec_file, "estimated_error"), std::nullopt);
    // The column holding the reference's uncertainty of y (half-width, y's unit), if any.
    if (const auto band = t["band"]) {
      if (!band.is_string()) throw CaseError(spec_file + ": key 'band': expected the name of a column (a string)");
      c.band = *band.value<std::string>();
    }
    // Further "key: value" lines (parameters, sampling, generator ...), after the
    // provenance, in the spec's order: extra = [["key", "value"], ...].
    if (const auto* more = t["extra"].as_array())
      for (const auto& kv : *more) {
        const auto* pair = kv.as_array();
        const auto k = pair && pair->size() == 2 ? (*pair)[0].value<std::string>() : std::nullopt;
        const auto v = pair && pair->size() == 2 ? (*pair)[1].value<std::string>() : std::nullopt;
        if (!k || !v) throw CaseError(spec_file + ": key 'extra': expected [[\"key\", \"value\"], ...]");
        c.extra.emplace_back(*k, *v);
      }
    require_checkable(c, reference::format_curve(c), spec_file, out);  // before anything is written
  } catch (const std::invalid_argument& e) {
    throw CaseError(spec_file + ": " + e.what());
  }
  reference::write_curve(out, c);
  return kOk;
}

}  // namespace cmc::app
