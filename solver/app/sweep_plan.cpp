// cmc sweep's points: the --over values, their product with --grids, and each point's folder.
#include "Sweep.hpp"

#include "commands.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>
#include <unordered_map>

#include <toml++/toml.h>

namespace cmc::app {

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

// The values of "V1,V2,...": split at the commas outside [], {} and quotes.
std::vector<std::string> split_values(const std::string& list, const std::string& argument) {
  std::vector<std::string> values;
  std::string current;
  int depth = 0;
  char quote = 0;
  for (char c : list) {
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '[' || c == '{') {
      ++depth;
    } else if (c == ']' || c == '}') {
      --depth;
    } else if (c == ',' && depth == 0) {
      values.push_back(trim(current));
      current.clear();
      continue;
    }
    current += c;
  }
  if (quote || depth != 0)
    throw CaseError("--over " + argument + ": an unclosed " + (quote ? "quote" : "bracket") + " in the values");
  values.push_back(trim(current));
  return values;
}

// One text per meaning of a TOML value, so that equal values are found by a hash: numbers by
// their value as a double (1 and 1.0, 1e4 and 10000; -0 as 0), strings and booleans by value,
// arrays element by element, tables key by key (toml++ keeps keys sorted). Nothing for a NaN,
// a date or a time (anywhere inside): those are the same only as written.
std::optional<std::string> meaning(const toml::node& v) {
  if (v.is_number()) {
    const std::optional<double> as_double = v.value<double>();
    if (!as_double || std::isnan(*as_double)) return std::nullopt;
    double d = *as_double;
    if (d == 0.0) d = 0.0;
    char buf[40];
    std::snprintf(buf, sizeof buf, "n%a", d);
    return std::string(buf);
  }
  if (v.is_string()) {
    const std::string s = *v.value<std::string>();
    return "s" + std::to_string(s.size()) + ":" + s;
  }
  if (v.is_boolean()) return std::string(*v.value<bool>() ? "b1" : "b0");
  std::string out;
  if (const toml::array* a = v.as_array()) {
    out = "[" + std::to_string(a->size());
    for (const toml::node& e : *a) {
      const auto m = meaning(e);
      if (!m) return std::nullopt;
      out += "," + *m;
    }
    return out + "]";
  }
  if (const toml::table* t = v.as_table()) {
    out = "{" + std::to_string(t->size());
    for (const auto& [key, e] : *t) {
      const auto m = meaning(e);
      if (!m) return std::nullopt;
      out += "," + std::to_string(key.str().size()) + ":" + std::string(key.str()) + "=" + *m;
    }
    return out + "}";
  }
  return std::nullopt;
}

// The key two values share exactly when they mean the same: their meaning where TOML reads
// them and it has one, else the text as written.
std::string value_key(const std::string& v) {
  try {
    const toml::table t = toml::parse("v = " + v);
    if (const auto m = meaning(*t.get("v"))) return "m" + *m;
  } catch (const toml::parse_error&) {
  }
  return "w" + v;
}

}  // namespace

SweepAxis parse_over(const std::string& argument) {
  const auto eq = argument.find('=');
  SweepAxis axis;
  axis.key = trim(argument.substr(0, eq));
  if (eq == std::string::npos || axis.key.empty() || axis.key.find('.') == std::string::npos ||
      axis.key.front() == '.' || axis.key.back() == '.')
    throw CaseError("--over " + argument + ": expected section.key=V1,V2,... (e.g. --over interaction.tabor=0.1,1.0)");
  const std::string list = trim(argument.substr(eq + 1));
  if (list.empty()) throw CaseError("--over " + argument + ": an empty list of values; expected " + axis.key + "=V1,V2,...");
  axis.values = split_values(list, argument);
  std::unordered_map<std::string, std::size_t> seen;  // each value's key: one look-up per value
  for (std::size_t i = 0; i < axis.values.size(); ++i) {
    if (axis.values[i].empty())
      throw CaseError("--over " + argument + ": value " + std::to_string(i + 1) + " is empty; expected " + axis.key +
                      "=V1,V2,... with a TOML value between each two commas");
    const auto [it, fresh] = seen.emplace(value_key(axis.values[i]), i);
    if (!fresh) {
      const std::string& first = axis.values[it->second];
      throw CaseError("--over " + argument + ": the value " + axis.values[i] +
                      (first == axis.values[i] ? "" : " (the same as " + first + ")") + " comes twice");
    }
  }
  return axis;
}

std::string SweepPoint::label() const {
  std::string s;
  for (const auto& [key, value] : values) s += (s.empty() ? "" : ", ") + key + "=" + value;
  if (grid > 0) s += (s.empty() ? "" : ", ") + std::string("n = ") + std::to_string(grid);
  return s.empty() ? "the case as it is" : s;
}

std::vector<SweepPoint> sweep_points(const std::vector<SweepAxis>& axes, const std::vector<int>& grids,
                                     const std::vector<std::string>& sets) {
  std::vector<SweepPoint> points{SweepPoint{{}, 0, sets, ""}};
  for (const SweepAxis& axis : axes) {
    std::vector<SweepPoint> next;
    for (const SweepPoint& p : points)
      for (const std::string& v : axis.values) {
        SweepPoint q = p;
        q.values.emplace_back(axis.key, v);
        q.sets.push_back(axis.key + "=" + v);
        next.push_back(std::move(q));
      }
    points = std::move(next);
  }
  if (grids.empty()) return points;
  std::vector<SweepPoint> with_grids;
  for (const SweepPoint& p : points)
    for (int n : grids) {
      SweepPoint q = p;
      q.grid = n;
      q.sets.push_back("grid.n=" + std::to_string(n));
      with_grids.push_back(std::move(q));
    }
  return with_grids;
}

std::string default_folder_pattern(const std::vector<SweepAxis>& axes, bool grids) {
  std::string pattern;
  for (const SweepAxis& a : axes) pattern += (pattern.empty() ? "" : "/") + a.key + "_{" + a.key + "}";
  if (grids || axes.empty()) pattern += (pattern.empty() ? "" : "/") + std::string("n{n}");
  return pattern;
}

std::string folder_text(const std::string& value) {
  std::string v = value;
  if (v.size() >= 2 && (v.front() == '"' || v.front() == '\'') && v.back() == v.front()) v = v.substr(1, v.size() - 2);
  for (char& c : v)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '+' && c != '-') c = '_';
  return v;
}

namespace {

// `pattern` with the point's placeholders filled in.
std::string expand(const std::string& pattern, const SweepPoint& p, const Case& c) {
  std::map<std::string, std::string> fill{{"n", std::to_string(c.grid.nx)}};
  for (const auto& [key, value] : p.values) fill[key] = folder_text(value);
  std::string out;
  for (std::size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '{') {
      out += pattern[i];
      continue;
    }
    const auto close = pattern.find('}', i);
    if (close == std::string::npos) throw CaseError("--folder " + pattern + ": an unclosed '{'");
    const std::string name = pattern.substr(i + 1, close - i - 1);
    const auto it = fill.find(name);
    if (it == fill.end())
      throw CaseError("--folder " + pattern + ": {" + name + "} is neither a swept key (--over) nor {n} (the grid)");
    out += it->second;
    i = close;
  }
  return out;
}

// A folder below the sweep's: relative, each part a name (not empty, "." or "..").
void check_relative_folder(const std::string& folder, const std::string& pattern, const SweepPoint& p) {
  const std::string where = "--folder " + pattern + ": the point " + p.label() + " gets the folder '" + folder + "'";
  if (folder.empty() || folder.front() == '/') throw CaseError(where + ": expected a relative path below --out");
  std::size_t start = 0;
  for (;;) {
    const auto slash = folder.find('/', start);
    const std::string part = folder.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
    if (part.empty() || part == "." || part == "..")
      throw CaseError(where + ": expected a relative path below --out, each part a name (not empty, '.' or '..')");
    if (part == ".partial" || part == ".cmc.lock")
      throw CaseError(where + ": '" + part + "' is the name of cmc's own files (a run's unfinished part, a folder's "
                      "lock); expected another name");
    if (slash == std::string::npos) return;
    start = slash + 1;
  }
}

}  // namespace

void sweep_folders(std::vector<SweepPoint>& points, const std::vector<Case>& cases, const std::string& pattern) {
  std::map<std::string, std::size_t> seen;
  for (std::size_t i = 0; i < points.size(); ++i) {
    SweepPoint& p = points[i];
    p.folder = expand(pattern, p, cases[i]);
    check_relative_folder(p.folder, pattern, p);
    const auto [it, fresh] = seen.emplace(p.folder, i);
    if (!fresh)
      throw CaseError("--folder " + pattern + ": the points " + points[it->second].label() + " and " + p.label() +
                      " share the folder " + p.folder + "; name every swept key ({KEY}) and, with --grids, {n} in it");
  }
}

}  // namespace cmc::app
