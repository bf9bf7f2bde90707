// Reference curves as files (see References.hpp and reference/README.md): a curve written
// and read back, the curves of cmc runs, and where the stored references live.
#include "ReferenceParts.hpp"

#include "cmc/input/DataDir.hpp"
#include "cmc/output/Writer.hpp"

#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <sstream>

namespace cmc::reference {

using namespace parts;

namespace {

// "%.12e", with -0 written as 0 so the output does not depend on the sign of a zero.
std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.12e", v == 0 ? 0.0 : v);
  return buf;
}

}  // namespace

Representation parse_representation(const std::string& s) {
  const std::string r = trim(s);
  if (r == "lin-lin") return {false, false};
  if (r == "log-lin") return {true, false};
  if (r == "lin-log") return {false, true};
  if (r == "log-log") return {true, true};
  throw InputError("representation '" + s + "': expected lin-lin, log-lin, lin-log or log-log (x-y axis scales)");
}

std::string format_curve(const Curve& c) {
  auto need = [&](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument("reference curve '" + c.name + "': " + what);
  };
  auto one_line = [](const std::string& s) { return s.find_first_of("\r\n") == std::string::npos; };
  need(!c.name.empty() && !c.quantity.empty() && !c.source.empty() && !c.estimated_error.empty(),
       "name, quantity, source and estimated_error are required");
  need(c.columns.size() >= 2, "needs at least two columns");
  parse_representation(c.representation);
  const std::size_t n = c.columns.front().values.size();
  need(n >= 1, "has no rows");
  bool has_x = false, has_y = false;
  for (const auto& col : c.columns) {
    need(!col.name.empty() && col.name.find_first_of(",\r\n# ") == std::string::npos,
         "column name '" + col.name + "' is empty or contains a comma, '#', space or newline");
    need(!col.unit.empty() && one_line(col.unit) && one_line(col.meaning), "column " + col.name + " needs a unit");
    need(col.values.size() == n, "column " + col.name + " has a different length");
    for (double v : col.values) need(std::isfinite(v), "column " + col.name + " holds a non-finite value");
    has_x |= col.name == c.x;
    has_y |= col.name == c.y;
  }
  need(has_x && has_y && c.x != c.y, "x and y must name two different columns");
  if (!c.band.empty()) {
    const Column* b = nullptr;
    const Column* y = nullptr;
    for (const auto& col : c.columns) {
      if (col.name == c.band) b = &col;
      if (col.name == c.y) y = &col;
    }
    need(b && b != y && b->name != c.x, "band must name a third column");
    need(b->unit == y->unit, "band column " + b->name + " must have y's unit (" + y->unit + ")");
    for (double v : b->values) need(v > 0, "band column " + b->name + " holds a value <= 0");
  }
  for (const auto& [k, v] : c.extra) need(valid_key(k) && one_line(v), "bad metadata '" + k + "'");
  for (const auto* s : {&c.name, &c.quantity, &c.title, &c.source, &c.estimated_error, &c.tolerance_metric})
    need(one_line(*s), "metadata must be one line each");

  std::string out;
  auto kv = [&](const std::string& k, const std::string& v) { out += "# " + k + ": " + v + "\n"; };
  kv("cmc-reference-csv", "1");
  kv("name", c.name);
  kv("quantity", c.quantity);
  if (!c.title.empty()) kv("title", c.title);
  kv("source", c.source);
  for (const auto& [k, v] : c.extra) kv(k, v);
  for (const auto& col : c.columns) kv("unit." + col.name, col.unit + (col.meaning.empty() ? "" : " (" + col.meaning + ")"));
  std::string names;
  for (const auto& col : c.columns) names += (names.empty() ? "" : ",") + col.name;
  kv("columns", names);
  kv("x", c.x);
  kv("y", c.y);
  kv("representation", c.representation);
  if (!c.band.empty()) kv("band", c.band);
  kv("estimated_error", c.estimated_error);
  if (c.tolerance) {
    kv("tolerance", short_num(*c.tolerance));
    kv("tolerance_metric", c.tolerance_metric);
  }
  out += names + "\n";
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t k = 0; k < c.columns.size(); ++k) {
      if (k) out += ',';
      out += num(c.columns[k].values[i]);
    }
    out += "\n";
  }
  return out;
}

void write_curve(const std::string& path, const Curve& c) {
  const std::string text = format_curve(c);
  const std::filesystem::path p(path);
  if (p.has_parent_path()) std::filesystem::create_directories(p.parent_path());
  write_output_text(p, text);
}

Curve curve_from_table(const Table& t) {
  Curve c;
  const std::string format = t.require("cmc-reference-csv");
  if (format != "1") throw InputError(t.file + ": format version '" + format + "' is not supported (expected 1)");
  c.name = t.require("name");
  c.quantity = t.require("quantity");
  c.title = t.get("title").value_or("");
  c.source = t.require("source");
  const std::string columns = t.require("columns");
  std::string header;
  for (const auto& n : t.columns) header += (header.empty() ? "" : ",") + n;
  if (columns != header)
    throw InputError(t.file + ":" + std::to_string(t.header_line) + ": header row '" + header +
                     "' differs from the metadata line '# columns: " + columns + "'");
  for (std::size_t k = 0; k < t.columns.size(); ++k) {
    Column col;
    col.name = t.columns[k];
    std::string u = t.require("unit." + col.name);
    const auto paren = u.find(" (");
    if (paren != std::string::npos && u.back() == ')') {
      col.meaning = u.substr(paren + 2, u.size() - paren - 3);
      u = u.substr(0, paren);
    }
    col.unit = u;
    col.values = t.data[k];
    c.columns.push_back(std::move(col));
  }
  c.x = t.require("x");
  c.y = t.require("y");
  t.column(c.x);
  t.column(c.y);
  c.representation = t.require("representation");
  try {
    parse_representation(c.representation);
  } catch (const InputError& e) {
    throw InputError(t.file + ": " + e.what());
  }
  if (auto band = t.get("band")) {
    c.band = *band;
    const std::vector<double>& b = t.column(c.band);
    if (c.band == c.x || c.band == c.y)
      throw InputError(t.file + ": '# band: " + c.band + "' must name a third column, not x or y");
    const std::string unit_b = t.require("unit." + c.band), unit_y = t.require("unit." + c.y);
    auto bare = [](const std::string& u) { return u.substr(0, u.find(" (")); };
    if (bare(unit_b) != bare(unit_y))
      throw InputError(t.file + ": band column '" + c.band + "' is in " + bare(unit_b) + ", y ('" + c.y + "') in " +
                       bare(unit_y) + ": the band is a half-width in y's unit");
    for (std::size_t i = 0; i < b.size(); ++i)
      if (!(b[i] > 0))
        throw InputError(t.file + ":" + std::to_string(t.row_line[i]) + ": band column '" + c.band + "': " +
                         short_num(b[i]) + " is not a half-width > 0");
  }
  c.estimated_error = t.require("estimated_error");
  if (auto tol = t.get("tolerance")) {
    char* end = nullptr;
    const double v = std::strtod(tol->c_str(), &end);
    if (end == tol->c_str() || *end != '\0' || !(v > 0) || !std::isfinite(v))
      throw InputError(t.file + ": '# tolerance: " + *tol + "' is not a positive number");
    c.tolerance = v;
    c.tolerance_metric = t.get("tolerance_metric").value_or("max_rel");
  }
  static const std::vector<std::string> fixed = {"cmc-reference-csv", "name", "quantity", "title", "source",
                                                 "columns", "x", "y", "representation", "estimated_error",
                                                 "tolerance", "tolerance_metric", "band"};
  for (const auto& [k, v] : t.meta)
    if (std::find(fixed.begin(), fixed.end(), k) == fixed.end() && k.rfind("unit.", 0) != 0) c.extra.emplace_back(k, v);
  return c;
}

Curve read_curve(const std::string& path) { return curve_from_table(read_csv(path, 2)); }

Curve parts::with_axes(Curve c, std::vector<Column> columns, const std::string& x, const std::string& y,
                       const std::string& representation, const std::string& estimated_error,
                       std::optional<double> tolerance, const std::string& tolerance_metric) {
  c.columns = std::move(columns);
  c.x = x;
  c.y = y;
  c.representation = representation;
  c.estimated_error = estimated_error;
  c.tolerance = tolerance;
  c.tolerance_metric = tolerance_metric;
  return c;
}

Curve make_run_curve(const std::string& name, const std::string& quantity, const std::string& title,
                     const RunProvenance& how, std::vector<Column> columns, const std::string& x,
                     const std::string& y, const std::string& representation,
                     const std::string& estimated_error, std::optional<double> tolerance,
                     const std::string& tolerance_metric) {
  Curve c;
  c.name = name;
  c.quantity = quantity;
  c.title = title;
  c.source = "cmc run";
#ifdef CMC_VERSION
  const std::string version = how.cmc_version.empty() ? std::string(CMC_VERSION) : how.cmc_version;
#else
  const std::string version = how.cmc_version;
#endif
  std::string date = how.date;
  if (date.empty()) {
    const std::time_t now = std::time(nullptr);
    std::tm tm{};
    gmtime_r(&now, &tm);
    char buf[32];
    std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
    date = buf;
  }
  c.extra = {{"cmc_version", version},    {"case_file", how.case_file}, {"grid", how.grid},
             {"solver_tolerance", how.solver_tolerance}, {"date", date}};
  if (!how.command.empty()) c.extra.emplace_back("command", how.command);
  return with_axes(std::move(c), std::move(columns), x, y, representation, estimated_error, tolerance,
                   tolerance_metric);
}

std::string default_reference_dir() {
  if (const char* env = std::getenv("CMC_REFERENCE_DIR"); env && *env) return env;
  const std::filesystem::path root = data::root();
  return root.empty() ? "reference" : (root / "reference").string();
}

std::string reference_dir_note() {
  if (const char* env = std::getenv("CMC_REFERENCE_DIR"); env && *env) return "";
  return data::root().empty() ? "; cmc's stored references were not found: " + data::places_text() : "";
}


}  // namespace cmc::reference
