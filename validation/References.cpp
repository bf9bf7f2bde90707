// Reference curves: CSV reader/writer and the analytic curve generators (see References.hpp
// and reference/README.md).
#include "References.hpp"

#include "cmc/analytic/Analytic.hpp"
#include "cmc/output/Writer.hpp"

#include <array>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <sstream>

namespace cmc::reference {

namespace {

constexpr double pi = std::numbers::pi;

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == sep) {
      out.push_back(cur);
      cur.clear();
    } else {
      cur += c;
    }
  }
  out.push_back(cur);
  return out;
}

// "%.12e", with -0 written as 0 so the output does not depend on the sign of a zero.
std::string num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.12e", v == 0 ? 0.0 : v);
  return buf;
}
// Short form for metadata (numbers quoted in headers, not data).
std::string short_num(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.6g", v == 0 ? 0.0 : v);
  return buf;
}

bool valid_key(const std::string& k) {
  if (k.empty()) return false;
  for (char c : k)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.' || c == '-')) return false;
  return true;
}

std::string where(const std::string& file, int line) { return file + ":" + std::to_string(line) + ": "; }

}  // namespace

// ============================================================================ Table
std::optional<std::string> Table::get(const std::string& key) const {
  for (const auto& [k, v] : meta)
    if (k == key) return v;
  return std::nullopt;
}

std::string Table::require(const std::string& key) const {
  auto v = get(key);
  if (!v || v->empty())
    throw InputError(file + ": the metadata line '# " + key + ": ...' is missing (see reference/README.md)");
  return *v;
}

void Table::set(const std::string& key, const std::string& value) {
  for (auto& [k, v] : meta)
    if (k == key) {
      v = value;
      return;
    }
  meta.emplace_back(key, value);
}

int Table::column_index(const std::string& name) const {
  for (std::size_t i = 0; i < columns.size(); ++i)
    if (columns[i] == name) return int(i);
  return -1;
}

const std::vector<double>& Table::column(const std::string& name) const {
  const int i = column_index(name);
  if (i < 0) {
    std::string have;
    for (const auto& c : columns) have += (have.empty() ? "" : ", ") + c;
    throw InputError(file + ":" + std::to_string(header_line) + ": no column '" + name + "' (the header has: " +
                     have + ")");
  }
  return data[std::size_t(i)];
}

namespace {
// A whole field that strtod reads as a number.
bool is_number(const std::string& f) {
  char* end = nullptr;
  std::strtod(f.c_str(), &end);
  return !f.empty() && end && *end == '\0';
}
const char* separator_name(char sep) {
  return sep == ',' ? "comma" : sep == ';' ? "semicolon" : "whitespace";
}
}  // namespace

std::vector<std::string> CsvReader::fields(const std::string& s) const {
  if (sep_ != ' ') return split(s, sep_);
  std::vector<std::string> out;
  std::size_t b = s.find_first_not_of(" \t");
  while (b != std::string::npos) {
    const std::size_t e = s.find_first_of(" \t", b);
    out.push_back(s.substr(b, e == std::string::npos ? std::string::npos : e - b));
    b = e == std::string::npos ? e : s.find_first_not_of(" \t", e);
  }
  return out;
}

CsvReader::CsvReader(std::istream& in, std::string file, bool keep_comments, Layout layout)
    : in_(in), keep_comments_(keep_comments), layout_(std::move(layout)) {
  t_.file = std::move(file);
  std::string raw;
  while (read_line(raw)) {
    if (line_ == 1 && raw.size() >= 3 && raw.compare(0, 3, "\xEF\xBB\xBF") == 0) raw.erase(0, 3);  // UTF-8 BOM
    const std::string s = trim(raw);
    if (s.empty()) continue;
    if (s[0] == '#') {
      const std::string body = trim(s.substr(1));
      const auto colon = body.find(':');
      if (colon != std::string::npos && valid_key(trim(body.substr(0, colon))))
        t_.set(trim(body.substr(0, colon)), trim(body.substr(colon + 1)));
      else
        t_.comments.push_back(body);
      continue;
    }
    if (layout_.any_separator)
      sep_ = s.find(',') != std::string::npos ? ',' : s.find(';') != std::string::npos ? ';' : ' ';
    auto fields = this->fields(s);
    have_header_ = true;
    t_.header_line = line_;
    bool numbers = layout_.any_separator;
    for (const auto& f : fields) numbers = numbers && is_number(trim(f));
    if (numbers) {  // no header row: this line is the first data row
      if (layout_.columns.empty())
        throw InputError(where(t_.file, line_) + "the file has no header row (this line is " +
                         std::to_string(fields.size()) + " numbers); name its columns with --columns, e.g. "
                         "--columns pressure_Pa,contact_fraction (cmc check --list gives the names)");
      if (layout_.columns.size() != fields.size())
        throw InputError(where(t_.file, line_) + "--columns names " + std::to_string(layout_.columns.size()) +
                         " columns, the file's rows have " + std::to_string(fields.size()) + " " +
                         separator_name(sep_) + "-separated values");
      pending_ = s, pending_line_ = line_;
      fields = layout_.columns;
    } else if (!layout_.columns.empty()) {
      if (layout_.columns.size() != fields.size())
        throw InputError(where(t_.file, line_) + "--columns names " + std::to_string(layout_.columns.size()) +
                         " columns, the header row has " + std::to_string(fields.size()));
      fields = layout_.columns;
    }
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const std::string name = trim(fields[k]);
      if (name.empty())
        throw InputError(where(t_.file, line_) + "header row: column " + std::to_string(k + 1) +
                         " has no name (expected comma-separated column names, e.g. "
                         "'pressure_Pa,contact_fraction')");
      if (is_number(name))
        throw InputError(where(t_.file, line_) + "header row: column " + std::to_string(k + 1) + " is the number '" +
                         name + "', expected a column name: the file needs a header row naming its columns, "
                         "e.g. 'pressure_Pa,contact_fraction'");
      if (std::find(t_.columns.begin(), t_.columns.end(), name) != t_.columns.end())
        throw InputError(where(t_.file, line_) + "header row: column name '" + name + "' appears twice");
      t_.columns.push_back(name);
    }
    if (t_.columns.size() < 2) {
      const bool other_sep = s.find_first_of("\t;") != std::string::npos || s.find(' ') != std::string::npos;
      throw InputError(where(t_.file, line_) + "header row '" + s + "' names one column; expected at least two, "
                       "separated by commas" + (layout_.any_separator ? ", semicolons, tabs or spaces"
                                                : other_sep ? " (tabs, spaces and semicolons are not separators)" : ""));
    }
    t_.data.assign(t_.columns.size(), {});
    return;
  }
}

bool CsvReader::read_line(std::string& raw) {
  raw.clear();
  std::streambuf* sb = in_.rdbuf();
  bool any = false;
  for (int ch = sb->sbumpc(); ch != std::char_traits<char>::eof(); ch = sb->sbumpc()) {
    any = true;
    if (ch == '\n') break;
    if (raw.size() >= kMaxLineBytes)
      throw InputError(where(t_.file, line_ + 1) + "line longer than " + std::to_string(kMaxLineBytes) +
                       " bytes (not a CSV file of numbers?)");
    raw.push_back(char(ch));
  }
  if (!any) return false;
  ++line_;
  return true;
}

bool CsvReader::next(std::vector<double>& values, int& line) {
  std::string raw;
  while (!pending_.empty() || read_line(raw)) {
    int at = line_;
    if (!pending_.empty()) raw = std::move(pending_), pending_.clear(), at = pending_line_;
    const std::string s = trim(raw);
    if (s.empty()) continue;
    if (s[0] == '#') {
      if (keep_comments_) t_.comments.push_back(trim(s.substr(1)));
      continue;
    }
    const auto fields = this->fields(s);
    if (fields.size() != t_.columns.size())
      throw InputError(where(t_.file, at) + "expected " + std::to_string(t_.columns.size()) + " " +
                       separator_name(sep_) + "-separated values (as in the header row, line " +
                       std::to_string(t_.header_line) + "), found " + std::to_string(fields.size()));
    values.resize(fields.size());
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const std::string f = trim(fields[k]);
      const std::string col = "column " + std::to_string(k + 1) + " ('" + t_.columns[k] + "'): ";
      if (f.empty()) throw InputError(where(t_.file, at) + col + "empty field, expected a number");
      errno = 0;
      char* end = nullptr;
      const double v = std::strtod(f.c_str(), &end);
      if (end == f.c_str() || *end != '\0')
        throw InputError(where(t_.file, at) + col + "'" + f + "' is not a number");
      if (!std::isfinite(v) || (errno == ERANGE && std::abs(v) > 1))
        throw InputError(where(t_.file, at) + col + "'" + f +
                         "' is not a finite number (NaN and infinity are not allowed)");
      values[k] = v;
    }
    line = at;
    return true;
  }
  return false;
}

void CsvReader::fail_no_header() const {
  throw InputError(t_.file + ": " + (line_ == 0 ? "the file is empty" : "the file has no header row and no data") +
                   " (expected a header row naming the columns, then one row of numbers per point)");
}

void CsvReader::fail_rows(std::size_t rows, std::size_t min_rows) const {
  throw InputError(t_.file + ": " + std::to_string(rows) + " data row" + (rows == 1 ? "" : "s") +
                   " after the header row (line " + std::to_string(t_.header_line) + "); expected at least " +
                   std::to_string(min_rows));
}

Table parse_csv(const std::string& text, const std::string& file, std::size_t min_rows) {
  std::istringstream in(text);
  CsvReader reader(in, file);
  if (!reader.has_header()) reader.fail_no_header();
  Table t = reader.header();
  std::vector<double> row;
  int line = 0;
  while (reader.next(row, line)) {
    for (std::size_t k = 0; k < row.size(); ++k) t.data[k].push_back(row[k]);
    t.row_line.push_back(line);
  }
  t.comments = reader.header().comments;  // including those after the header
  if (t.rows() < min_rows) reader.fail_rows(t.rows(), min_rows);
  return t;
}

std::ifstream open_csv(const std::string& path) {
  if (const std::string why = input_file_problem(path); !why.empty()) throw InputError(path + ": " + why);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot be read");
  return in;
}

Table read_csv(const std::string& path, std::size_t min_rows) {
  std::ifstream in = open_csv(path);
  std::ostringstream s;
  s << in.rdbuf();
  return parse_csv(s.str(), path, min_rows);
}

// ============================================================================ curves
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

// ============================================================================ cmc runs
namespace {
// The part every curve ends with: its columns, axes, representation, error statement
// and tolerance.
Curve with_axes(Curve c, std::vector<Column> columns, const std::string& x, const std::string& y,
                const std::string& representation, const std::string& estimated_error, std::optional<double> tolerance,
                const std::string& tolerance_metric) {
  c.columns = std::move(columns);
  c.x = x;
  c.y = y;
  c.representation = representation;
  c.estimated_error = estimated_error;
  c.tolerance = tolerance;
  c.tolerance_metric = tolerance_metric;
  return c;
}

}  // namespace

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

// ============================================================================ analytic curves
namespace {

namespace an = cmc::analytic;

Curve base(const std::string& name, const std::string& quantity, const std::string& title, const std::string& source) {
  Curve c;
  c.name = name;
  c.quantity = quantity;
  c.title = title;
  c.source = "analytic: " + source;
  c.extra.emplace_back("generator", "cmc reference " + name + " (validation/References.cpp, solver/cmc/analytic/Analytic.cpp)");
  return c;
}
// The same, with the units and sampling lines that most curves state next.
Curve base(const std::string& name, const std::string& quantity, const std::string& title, const std::string& source,
           const std::string& units, const std::string& sampling) {
  Curve c = base(name, quantity, title, source);
  c.extra.emplace_back("units", units);
  c.extra.emplace_back("sampling", sampling);
  return c;
}

// Samples a curve at x = k / div, k = k0..k1: x goes to `x`, the values f(x) returns (an
// array, one per column) to `ys`.
template <std::size_t K, class F>
void sample(Column& x, const std::array<Column*, K>& ys, int k0, int k1, double div, F f) {
  for (int k = k0; k <= k1; ++k) {
    const double v = k / div;
    const std::array<double, K> y = f(v);
    x.values.push_back(v);
    for (std::size_t i = 0; i < K; ++i) ys[i]->values.push_back(y[i]);
  }
}

const char* kRoundOff = "closed form evaluated in double precision, stored with 13 significant digits: "
                        "< 1e-12 relative";

Curve hertz_penetration_force() {
  Curve c = base("hertz_penetration_force", "penetration_vs_force", "Hertz: penetration and contact radius vs force",
                 "Hertz (1882); Johnson, Contact Mechanics (1985) eqs. 4.22-4.23: a^3 = 3FR/(4E*), delta = a^2/R, "
                 "i.e. F = (4/3) E* R^(1/2) delta^(3/2)",
                 "reduced: force in E* R^2, lengths in R (R = sphere radius, E* = contact modulus)",
                 "F/(E* R^2) = 10^(-9 + k/10), k = 0..60");
  Column F{"F_over_EstarR2", "1", "F/(E* R^2)", {}}, d{"delta_over_R", "1", "penetration delta/R", {}},
      a{"a_over_R", "1", "contact radius a/R", {}};
  for (int k = 0; k <= 60; ++k) {
    const double f = std::pow(10.0, -9.0 + k / 10.0);
    const auto h = an::hertz_from_force(1.0, 1.0, f);
    F.values.push_back(f);
    d.values.push_back(h.penetration);
    a.values.push_back(h.radius);
  }
  // the validation suite's penetration tolerance (cases/validation/hertz-*.toml)
  return with_axes(std::move(c), {F, d, a}, F.name, d.name, "log-log",
                   kRoundOff, 1e-3, "max_rel");
}

Curve hertz_pressure_profile() {
  Curve c = base("hertz_pressure_profile", "pressure_profile", "Hertz: pressure profile p(r)/p0 vs r/a",
                 "Hertz (1882); Johnson, Contact Mechanics (1985) eq. 4.22: p(r) = p0 sqrt(1 - r^2/a^2) for r < a, "
                 "0 outside, p0 = 2 E* a/(pi R) = 3F/(2 pi a^2)",
                 "reduced: r in the contact radius a, p in the peak pressure p0 (independent of load)",
                 "r/a = k/100, k = 0..150");
  Column r{"r_over_a", "1", "radial distance r/a", {}}, p{"p_over_p0", "1", "pressure p/p0", {}};
  const double a = 0.1;
  const double p0 = an::hertz_from_radius(1.0, 1.0, a).max_pressure;
  sample<1>(r, {&p}, 0, 150, 100.0, [&](double x) { return std::array{an::hertz_pressure(1.0, 1.0, a, x * a) / p0}; });
  // the validation suite's pressure_profile tolerance (in units of p0)
  return with_axes(std::move(c), {r, p}, r.name, p.name, "lin-lin",
                   kRoundOff, 1e-2, "max_abs");
}

const char* kWestergaardSource =
    "Westergaard (1939); Johnson, Contact Mechanics (1985) sec. 13.2; Johnson, Int. J. Solids Struct. 32, 423 "
    "(1995) eq. 4: profile h(x) = 2h sin^2(pi x/lambda), p* = pi E* h/lambda, pbar = p* sin^2(pi a/lambda), "
    "p(x) = 2 p* cos(pi x/lambda) sqrt(sin^2(pi a/lambda) - sin^2(pi x/lambda)) for |x| < a";

Curve westergaard_mean_pressure() {
  Curve c = base("westergaard_mean_pressure", "mean_pressure_vs_half_width",
                 "Westergaard wavy contact: mean pressure vs contact half-width", kWestergaardSource,
                 "reduced: lengths in the wavelength lambda, pressure in p* = pi E* h/lambda",
                 "a/lambda = k/200, k = 0..100");
  Column a{"a_over_lambda", "1", "contact half-width a/lambda", {}}, p{"pbar_over_pstar", "1", "mean pressure pbar/p*", {}};
  const double pstar = an::westergaard_full_contact_pressure(1.0, 1.0, 1.0);
  sample<1>(a, {&p}, 0, 100, 200.0,
            [&](double x) { return std::array{an::westergaard_mean_pressure(1.0, 1.0, 1.0, x) / pstar}; });
  return with_axes(std::move(c), {a, p}, a.name, p.name, "lin-lin",
                   kRoundOff, 1e-3, "max_abs");
}

Curve westergaard_mean_gap() {
  Curve c = base("westergaard_mean_gap", "mean_gap_vs_pressure", "Westergaard wavy contact: mean gap vs mean pressure",
                 std::string(kWestergaardSource) +
                     "; mean gap gbar = h (1 - t + t ln t), t = pbar/p* (Carbone & Mangialardi, JMPS 52, 1267 "
                     "(2004) eq. 39)",
                 "reduced: pressure in p* = pi E* h/lambda, gap in the amplitude h",
                 "pbar/p* = 10^(-4 + k/10), k = 0..40");
  Column p{"pbar_over_pstar", "1", "mean pressure pbar/p*", {}}, g{"mean_gap_over_h", "1", "mean gap / h", {}};
  const double pstar = an::westergaard_full_contact_pressure(1.0, 1.0, 1.0);
  for (int k = 0; k <= 40; ++k) {
    const double x = std::pow(10.0, -4.0 + k / 10.0);
    p.values.push_back(x);
    g.values.push_back(an::westergaard_mean_gap(1.0, 1.0, 1.0, x * pstar));
  }
  return with_axes(std::move(c), {p, g}, p.name, g.name, "log-lin",
                   kRoundOff, 1e-3, "max_abs");
}

Curve westergaard_pressure_profile() {
  Curve c = base("westergaard_pressure_profile", "pressure_profile",
                 "Westergaard wavy contact: pressure profiles at pbar/p* = 0.1, 0.3, 0.6, 0.9", kWestergaardSource,
                 "reduced: x in the wavelength lambda (from the contact centre), pressure in p*",
                 "x/lambda = k/200, k = -100..100");
  const std::vector<double> loads = {0.1, 0.3, 0.6, 0.9};
  const double pstar = an::westergaard_full_contact_pressure(1.0, 1.0, 1.0);
  Column x{"x_over_lambda", "1", "position x/lambda from the contact centre", {}};
  std::vector<Column> cols;
  for (double l : loads) {
    char name[64];
    std::snprintf(name, sizeof name, "p_over_pstar_at_%.1f", l);
    Column col{name, "1", "p/p* at pbar/p* = " + short_num(l), {}};
    const double a = an::westergaard_half_width(1.0, 1.0, 1.0, l * pstar);
    for (int k = -100; k <= 100; ++k) col.values.push_back(an::westergaard_pressure(1.0, 1.0, 1.0, a, k / 200.0) / pstar);
    cols.push_back(col);
  }
  for (int k = -100; k <= 100; ++k) x.values.push_back(k / 200.0);
  cols.insert(cols.begin(), x);
  // the validation suite's pressure_profile tolerance (in units of p*)
  return with_axes(std::move(c), cols, x.name, cols[1].name, "lin-lin", kRoundOff, 1e-2, "max_abs");
}

Curve jkr_force_penetration() {
  Curve c = base("jkr_force_penetration", "force_vs_penetration",
                 "JKR: force and penetration vs contact radius (both branches)",
                 "Johnson, Kendall & Roberts, Proc. R. Soc. A 324, 301 (1971); Maugis, Contact, Adhesion and "
                 "Rupture of Elastic Solids (2000) ch. 5: F = 4E* a^3/(3R) - sqrt(8 pi w E* a^3), "
                 "delta = a^2/R - sqrt(2 pi w a/E*); in Maugis' units Pbar = A^3 - sqrt(6 A^3), "
                 "Delta = A^2 - (2/3) sqrt(6 A)");
  c.extra.emplace_back("units",
                       "reduced (Maugis, J. Colloid Interface Sci. 150, 243 (1992)), K = 4E*/3: A = a/(pi w R^2/K)^(1/3), "
                       "Pbar = F/(pi w R), Delta = delta/(pi^2 w^2 R/K^2)^(1/3)");
  const double Es = 1.0, R = 1.0, w = 1.0;
  const auto s = an::md_scales(Es, R, w);
  const auto lc = an::jkr_pulloff_load_controlled(Es, R, w);
  const auto dc = an::jkr_pulloff_displacement_controlled(Es, R, w);
  c.extra.emplace_back("branches",
                       "parametrised by A (monotonic); under load control A < " + short_num(lc.radius / s.radius) +
                           " is unstable (pull-off at Pbar = " + short_num(lc.force / s.force) +
                           "); under displacement control A < " + short_num(dc.radius / s.radius) +
                           " is unstable (pull-off at Delta = " + short_num(dc.penetration / s.penetration) +
                           ", Pbar = " + short_num(dc.force / s.force) + ")");
  c.extra.emplace_back("sampling", "A = k/50, k = 0..150");
  Column A{"A", "1", "reduced contact radius", {}}, P{"Pbar", "1", "reduced force F/(pi w R)", {}},
      D{"Delta", "1", "reduced penetration", {}};
  sample<2>(A, {&P, &D}, 0, 150, 50.0, [&](double x) {
    return std::array{an::jkr_force(Es, R, w, x * s.radius) / s.force,
                      an::jkr_penetration(Es, R, w, x * s.radius) / s.penetration};
  });
  return with_axes(std::move(c), {A, P, D}, A.name, P.name, "lin-lin",
                   kRoundOff, 1e-2, "max_abs");
}

Curve maugis_dugdale(double lambda, const std::string& tag) {
  Curve c = base("maugis_dugdale_lambda_" + tag, "force_vs_penetration",
                 "Maugis-Dugdale: force and penetration vs contact radius at lambda = " + tag,
                 "Maugis, J. Colloid Interface Sci. 150, 243 (1992) eqs. 6.17-6.19 with m = c/a, mu = sqrt(m^2-1): "
                 "(lambda A^2/2)[mu + (m^2-2) atan mu] + (4 lambda^2 A/3)[mu atan mu - m + 1] = 1, "
                 "Pbar = A^3 - lambda A^2 [mu + m^2 atan mu], Delta = A^2 - (4/3) lambda A mu");
  c.extra.emplace_back("parameters", "lambda = " + tag + " (lambda = 2 sigma0 (R/(pi w K^2))^(1/3); for exponential "
                                     "adhesion with sigma0 = w/rho, lambda = 2 (9/(16 pi))^(1/3) mu_T ~ 1.127 mu_T)");
  c.extra.emplace_back("units",
                       "reduced (Maugis 1992), K = 4E*/3: A = a/(pi w R^2/K)^(1/3), Pbar = F/(pi w R), "
                       "Delta = delta/(pi^2 w^2 R/K^2)^(1/3), m = c/a (c = outer radius of the cohesive zone)");
  const auto end = an::md_zero_radius_limit(lambda);
  const auto po = an::md_pulloff(lambda);
  c.extra.emplace_back("limits", "A -> 0: Pbar = " + short_num(end.Pbar) + ", Delta = " + short_num(end.Delta) +
                                     "; load-controlled pull-off at A = " + short_num(po.A) + ", Pbar = " +
                                     short_num(po.Pbar));
  c.extra.emplace_back("sampling", "A = k/50, k = 1..150");
  Column A{"A", "1", "reduced contact radius", {}}, m{"m", "1", "c/a", {}}, P{"Pbar", "1", "reduced force F/(pi w R)", {}},
      D{"Delta", "1", "reduced penetration", {}};
  for (int k = 1; k <= 150; ++k) {
    const auto pt = an::md_point(lambda, k / 50.0);
    A.values.push_back(pt.A);
    m.values.push_back(pt.m);
    P.values.push_back(pt.Pbar);
    D.values.push_back(pt.Delta);
  }
  return with_axes(std::move(c), {A, P, D, m}, A.name, P.name, "lin-lin",
                   "root of the Maugis equation for m to 1e-14 relative (GSL Brent), stored with 13 significant "
                      "digits: < 1e-12 relative", 1e-2, "max_abs");
}

Curve johnson_sinusoid(double alpha, const std::string& tag) {
  Curve c = base("johnson_sinusoid_alpha_" + tag, "mean_pressure_vs_half_width",
                 "Johnson (1995) adhesive wavy contact: mean pressure and mean gap vs half-width at alpha = " + tag,
                 "Johnson, Int. J. Solids Struct. 32, 423 (1995): pbar/p* = sin^2(pi a/lambda) - alpha "
                 "sqrt(tan(pi a/lambda)), alpha = sqrt(2 w lambda/E*)/(pi h), p* = pi E* h/lambda; mean gap "
                 "gbar = h [1 - t + (pbar/p*) ln t], t = sin^2(pi a/lambda) (Carbone & Mangialardi, JMPS 52, 1267 "
                 "(2004) eq. 39)");
  c.extra.emplace_back("parameters", "alpha = " + tag + "; profile h(x) = 2h sin^2(pi x/lambda)");
  c.extra.emplace_back("units", "reduced: lengths in the wavelength lambda, pressure in p*, gap in the amplitude h");
  const double Es = 1.0, h = 1.0, L = 1.0;
  const double w = std::pow(alpha * pi * h, 2) * Es / (2 * L);
  const double pstar = an::westergaard_full_contact_pressure(Es, h, L);
  const auto po = an::johnson_pulloff(Es, w, h, L);
  c.extra.emplace_back("branches", "load-controlled pull-off at a/lambda = " + short_num(po.half_width / L) +
                                       ", pbar/p* = " + short_num(po.mean_pressure / pstar) +
                                       "; smaller a is unstable under load control; spontaneous full contact at "
                                       "zero load for alpha > " + short_num(an::johnson_full_contact_alpha()));
  c.extra.emplace_back("sampling", "a/lambda = k/200, k = 1..99");
  Column a{"a_over_lambda", "1", "contact half-width a/lambda", {}}, p{"pbar_over_pstar", "1", "mean pressure pbar/p*", {}},
      g{"mean_gap_over_h", "1", "mean gap / h", {}};
  sample<2>(a, {&p, &g}, 1, 99, 200.0, [&](double x) {
    return std::array{an::johnson_mean_pressure(Es, w, h, L, x * L) / pstar, an::johnson_mean_gap(Es, w, h, L, x * L) / h};
  });
  // mean pressure within 1e-2 p* (the ContactMechanics test suite's bound)
  return with_axes(std::move(c), {a, p, g}, a.name, p.name, "lin-lin",
                   kRoundOff, 1e-2, "max_abs");
}

struct Generator {
  std::string name;
  std::function<Curve()> make;
};

const std::vector<Generator>& generators() {
  static const std::vector<Generator> g = {
      {"hertz_penetration_force", hertz_penetration_force},
      {"hertz_pressure_profile", hertz_pressure_profile},
      {"westergaard_mean_pressure", westergaard_mean_pressure},
      {"westergaard_mean_gap", westergaard_mean_gap},
      {"westergaard_pressure_profile", westergaard_pressure_profile},
      {"jkr_force_penetration", jkr_force_penetration},
      {"maugis_dugdale_lambda_0.3", [] { return maugis_dugdale(0.3, "0.3"); }},
      {"maugis_dugdale_lambda_1", [] { return maugis_dugdale(1.0, "1"); }},
      {"maugis_dugdale_lambda_3", [] { return maugis_dugdale(3.0, "3"); }},
      {"johnson_sinusoid_alpha_0.1", [] { return johnson_sinusoid(0.1, "0.1"); }},
      {"johnson_sinusoid_alpha_0.3", [] { return johnson_sinusoid(0.3, "0.3"); }},
      {"johnson_sinusoid_alpha_0.5", [] { return johnson_sinusoid(0.5, "0.5"); }},
  };
  return g;
}

}  // namespace

std::vector<std::string> analytic_curve_names() {
  std::vector<std::string> n;
  for (const auto& g : generators()) n.push_back(g.name);
  return n;
}

Curve generate(const std::string& name) {
  for (const auto& g : generators())
    if (g.name == name) return g.make();
  std::string known;
  for (const auto& g : generators()) known += (known.empty() ? "" : ", ") + g.name;
  throw std::invalid_argument("unknown reference curve '" + name + "' (known: " + known + ")");
}

std::string analytic_curve_title(const std::string& name) { return generate(name).title; }

std::string default_reference_dir() {
  if (const char* env = std::getenv("CMC_REFERENCE_DIR"); env && *env) return env;
#ifdef CMC_SOURCE_DIR
  return std::string(CMC_SOURCE_DIR) + "/reference";
#else
  return "reference";
#endif
}

}  // namespace cmc::reference
