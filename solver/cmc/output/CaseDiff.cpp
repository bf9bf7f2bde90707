#include "cmc/output/CaseDiff.hpp"

#include "cmc/input/Case.hpp"

#include <cstdlib>
#include <map>
#include <sstream>

namespace cmc {

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

// "section.key" -> value text, from the layout toml++'s json_formatter gives a resolved
// case: one key per line, nested tables opened by `"name" : {` and closed by `}`, arrays
// spread over lines (joined here with single spaces). Only this layout is read: the text
// is cmc's own.
std::map<std::string, std::string> flatten(const std::string& json) {
  std::map<std::string, std::string> out;
  std::vector<std::string> path;
  std::istringstream in(json);
  std::string line, array_key, array_text;
  int array_depth = 0;
  while (std::getline(in, line)) {
    std::string t = trim(line);
    if (array_depth > 0) {
      for (char ch : t) array_depth += ch == '[' ? 1 : ch == ']' ? -1 : 0;
      if (array_depth == 0 && !t.empty() && t.back() == ',') t.pop_back();
      array_text += (array_text.back() == '[' || t == "]" ? "" : " ") + t;
      if (array_depth == 0) out[array_key] = array_text;
      continue;
    }
    if (t == "{" || t.empty()) continue;
    if (t == "}" || t == "},") {
      if (!path.empty()) path.pop_back();
      continue;
    }
    if (t.front() != '"') continue;
    const auto close = t.find('"', 1);
    const auto colon = t.find(':', close);
    if (close == std::string::npos || colon == std::string::npos) continue;
    const std::string key = t.substr(1, close - 1);
    std::string value = trim(t.substr(colon + 1));
    if (value.empty()) continue;
    std::string full;
    for (const auto& p : path) full += p + ".";
    full += key;
    if (value == "{") {
      path.push_back(key);
      continue;
    }
    if (value.front() == '[') {
      int depth = 0;
      for (char ch : value) depth += ch == '[' ? 1 : ch == ']' ? -1 : 0;
      if (depth > 0) {
        array_depth = depth, array_key = full, array_text = value;
        continue;
      }
    }
    if (!value.empty() && value.back() == ',') value.pop_back();
    out[full] = value;
  }
  return out;
}

// A value as JSON writes it against a documented default as cases/README.md writes it:
// equal as text, or as numbers.
bool is_default(const std::string& value, const std::string& text) {
  if (value == text) return true;
  char* end1 = nullptr;
  char* end2 = nullptr;
  const double a = std::strtod(value.c_str(), &end1);
  const double b = std::strtod(text.c_str(), &end2);
  return end1 != value.c_str() && *end1 == '\0' && end2 != text.c_str() && *end2 == '\0' && a == b;
}

// Keys that only say when a solve gives up (see CaseDiff.hpp).
bool is_stopping_limit(const std::string& key) { return key == "solver.max_outer_steps"; }

}  // namespace

CaseDiff compare_cases(const std::string& checkpoint_json, const std::string& current_json) {
  const auto was = flatten(checkpoint_json);
  const auto now = flatten(current_json);
  std::map<std::string, std::string> defaults;
  for (const auto& d : case_defaults()) defaults[d.section + "." + d.key] = d.text;
  CaseDiff diff;
  for (const auto& [key, value] : was) {
    const auto it = now.find(key);
    if (it == now.end()) {
      diff.mismatch = "key " + key + ": " + value + " in the checkpoint, absent here";
      return diff;
    }
    if (it->second != value && key == "case.description") {
      diff.text_changed.push_back(key);
    } else if (it->second != value && is_stopping_limit(key)) {
      diff.limits_changed.push_back(key + ": " + value + " in the checkpoint, " + it->second + " here");
    } else if (it->second != value) {
      diff.mismatch = "key " + key + ": " + value + " in the checkpoint, " + it->second + " here";
      return diff;
    }
  }
  for (const auto& [key, value] : now) {
    if (was.count(key)) continue;
    const auto d = defaults.find(key);
    if (d != defaults.end() && is_stopping_limit(key) && !is_default(value, d->second)) {
      // The older version stopped at the default: that is the checkpoint's limit.
      diff.limits_changed.push_back(key + ": " + d->second + " (its default) in the checkpoint, " + value + " here");
      continue;
    }
    if (d == defaults.end() || !is_default(value, d->second)) {
      diff.mismatch = "key " + key + ": absent from the checkpoint, " + value + " here" +
                      (d == defaults.end() ? std::string() : " (its default is " + d->second + ")");
      return diff;
    }
    diff.defaulted.push_back(key + " = " + value);
  }
  return diff;
}

}  // namespace cmc
