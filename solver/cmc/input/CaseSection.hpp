// The case parser's pieces (input/Case.cpp, input/CaseSections.cpp, input/CaseDefaults.cpp):
// typed access to one section of a case file, with the messages every key's error uses,
// and the parsers of the sections. Internal to the input layer.
#pragma once

#include "cmc/input/Case.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace cmc::case_parsing {

// A number as cases/README.md writes it: the shortest form that reads back the same.
inline std::string number_text(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  std::string t(buf, r.ptr);
  // 1e-08 -> 1e-8: exponents without leading zeros, as a person writes them.
  const auto e = t.find('e');
  if (e != std::string::npos) {
    const std::size_t digits = t[e + 1] == '-' || t[e + 1] == '+' ? e + 2 : e + 1;
    while (t.size() > digits + 1 && t[digits] == '0') t.erase(digits, 1);
  }
  return t;
}
inline std::string where(const toml::node* n) {
  if (!n) return "";
  const auto& s = n->source();
  if (!s.begin) return "";
  return " (line " + std::to_string(s.begin.line) + ")";
}

inline std::string type_name(const toml::node& n) {
  switch (n.type()) {
    case toml::node_type::string: return "a string";
    case toml::node_type::integer: return "an integer";
    case toml::node_type::floating_point: return "a number";
    case toml::node_type::boolean: return "a boolean";
    case toml::node_type::array: return "an array";
    case toml::node_type::table: return "a table";
    default: return "a date or time";
  }
}

// Typed access to one section, remembering which keys were read so that the rest
// can be reported as unknown. Defaults are written back into the table so that the
// resolved case shows every value that was used.
class Section {
 public:
  Section(toml::table& root, std::string name, const std::string& file, bool required)
      : file_(file), name_(std::move(name)) {
    toml::node* n = root.get(name_);
    if (!n) {
      if (required) fail_missing_section();
      root.insert(name_, toml::table{});
      n = root.get(name_);
    }
    if (!n->is_table()) throw CaseError(file_ + ": [" + name_ + "] must be a table" + where(n));
    t_ = n->as_table();
  }
  Section(toml::table& t, std::string name, const std::string& file) : file_(file), name_(std::move(name)), t_(&t) {}

  bool has(const std::string& key) const { return t_->contains(key); }

  std::string key_name(const std::string& key) const { return "[" + name_ + "] " + key; }

  [[noreturn]] void fail(const std::string& key, const std::string& expected) const {
    const toml::node* n = t_->get(key);
    std::string got;
    if (n) {
      std::ostringstream s;
      n->visit([&](auto&& v) { s << v; });
      std::string text = s.str();
      if (text.size() > 80) text = text.substr(0, 80) + "... (" + std::to_string(text.size()) + " characters)";
      got = ", got " + type_name(*n) + " " + text;
    }
    throw CaseError(file_ + ": " + key_name(key) + ": expected " + expected + got + where(n));
  }

  std::string string(const std::string& key, std::optional<std::string> def = {}, std::set<std::string> choices = {}) {
    std::string expected = "a string";
    if (!choices.empty()) {
      expected = "one of";
      for (const auto& c : choices) expected += " \"" + c + "\"";
    }
    const toml::node* n = given(key, def, expected);
    if (!n) return *def;
    if (!n->is_string()) fail(key, expected);
    std::string v = n->as_string()->get();
    if (!choices.empty() && !choices.count(v)) fail(key, expected);
    return v;
  }

  // One of the words of kind_names(E) (input/Kinds.hpp), as its typed value. A default
  // is written back as its word, like every other default.
  template <class E>
  E choice(const std::string& key, std::optional<E> def = {}) {
    std::set<std::string> words;
    for (const auto& k : kind_names(E{})) words.insert(std::string(k.name));
    const std::optional<std::string> word = def ? std::optional(std::string(kind_name(*def))) : std::nullopt;
    const std::string v = string(key, word, words);
    for (const auto& k : kind_names(E{}))
      if (k.name == v) return k.value;
    fail(key, "a known word");  // unreachable: string() checked the choices
  }
  // Replace the value of `key` in the resolved case (e.g. a kind resolved from "auto").
  void resolve(const std::string& key, const std::string& value) { t_->insert_or_assign(key, value); }

  double number(const std::string& key, std::optional<double> def, const std::string& what,
                bool positive = false, bool non_negative = false) {
    const toml::node* n = given(key, def, what);
    if (!n) return *def;
    double v;
    if (auto f = n->as_floating_point()) v = f->get();
    else if (auto i = n->as_integer()) v = double(i->get());
    else fail(key, what);
    if (!std::isfinite(v)) fail(key, what + " (finite)");
    if (positive && !(v > 0.0)) fail(key, what + " (> 0)");
    if (non_negative && !(v >= 0.0)) fail(key, what + " (>= 0)");
    return v;
  }

  // An integer in [min, max]; max defaults to int's, as most keys are read into an int
  // (a larger value would wrap around: n = 2^32 + 1 was read as 1). Sizes have their own
  // bounds (CaseLimits).
  long long integer(const std::string& key, std::optional<long long> def, const std::string& what, long long min,
                    long long max = std::numeric_limits<int>::max()) {
    const toml::node* n = given(key, def, what);
    if (!n) return *def;
    auto i = n->as_integer();
    if (!i) fail(key, what + (n->is_floating_point() ? " (a whole number, written without a decimal point)" : ""));
    if (i->get() < min) fail(key, what + " (>= " + std::to_string(min) + ")");
    if (i->get() > max) fail(key, what + " (<= " + std::to_string(max) + ")");
    return i->get();
  }

  bool boolean(const std::string& key, bool def) {
    const toml::node* n = given(key, std::optional<bool>(def), "true or false");
    if (!n) return def;
    if (!n->is_boolean()) fail(key, "true or false");
    return n->as_boolean()->get();
  }

  std::vector<double> numbers(const std::string& key, const std::string& what, std::size_t min_len = 1) {
    used_.insert(key);
    const toml::node* n = t_->get(key);
    if (!n) fail_missing(key, what);
    auto a = n->as_array();
    if (!a || a->size() < min_len) fail(key, what);
    std::vector<double> v;
    for (const auto& e : *a) {
      if (auto f = e.as_floating_point()) v.push_back(f->get());
      else if (auto i = e.as_integer()) v.push_back(double(i->get()));
      else fail(key, what);
      if (!std::isfinite(v.back())) fail(key, what + " (finite numbers)");
    }
    return v;
  }

  toml::table* subtable(const std::string& key) {
    toml::node* n = optional(key, toml::node_type::table, "a table");
    return n ? n->as_table() : nullptr;
  }
  toml::array* array(const std::string& key) {
    toml::node* n = optional(key, toml::node_type::array, "an array");
    return n ? n->as_array() : nullptr;
  }
  void ignore(const std::string& key) { used_.insert(key); }

  // Every key not read is a mistake (a typo, or a key of another kind: `owners` says which
  // kinds a documented key belongs to, e.g. {"radius", "kind = \"sphere\""}).
  void finish(const std::vector<std::pair<std::string, std::string>>& owners = {}) const {
    for (const auto& [k, v] : *t_) {
      const std::string key(k.str());
      if (used_.count(key)) continue;
      for (const auto& [owned, kinds] : owners)
        if (owned == key)
          throw CaseError(file_ + ": " + key_name(key) + ": applies only with " + kinds + " (this case's kind is \"" +
                          (*t_)["kind"].value_or(std::string("?")) + "\")" + where(&v) + ": remove it");
      throw CaseError(file_ + ": " + key_name(key) + ": unknown key" + where(&v) + " (see cases/README.md for the keys of [" +
                      name_ + "])");
    }
  }

 private:
  // The node of `key` as given, or nullptr when it is absent: then its default is written
  // into the resolved case (an absent key without a default is an error).
  template <class T>
  const toml::node* given(const std::string& key, const std::optional<T>& def, const std::string& expected) {
    used_.insert(key);
    const toml::node* n = t_->get(key);
    if (!n) {
      if (!def) fail_missing(key, expected);
      t_->insert(key, *def);
    }
    return n;
  }
  // An optional key of the given type (nullptr when absent).
  toml::node* optional(const std::string& key, toml::node_type type, const std::string& expected) {
    used_.insert(key);
    toml::node* n = t_->get(key);
    if (n && n->type() != type) fail(key, expected);
    return n;
  }
  [[noreturn]] void fail_missing(const std::string& key, const std::string& expected) const {
    throw CaseError(file_ + ": " + key_name(key) + ": missing required key, expected " + expected);
  }
  [[noreturn]] void fail_missing_section() const {
    throw CaseError(file_ + ": missing required section [" + name_ + "]");
  }
  std::string file_, name_;
  toml::table* t_;
  std::set<std::string> used_;
};

void parse_grid(Section s, GridSpec& g);
void parse_surface(Section s, const GridSpec& grid, SurfaceSpec& sf);
void parse_interaction(Section s, SurfaceKind surface, InteractionSpec& in);
void parse_loading(Section s, bool adhesive, bool periodic, LoadingSpec& l);
void parse_solver(Section s, const InteractionSpec& in, const LoadingSpec& l, SolverSpec& sv);
void parse_observables(Section s, double size_x, ObservablesSpec& o);
// [validation] (input/CaseValidation.cpp); `resolved`: the case's other sections, which a
// continuity check's parameter must name.
ValidationSpec parse_validation(Section s, const std::string& file, const toml::table& resolved);

}  // namespace cmc::case_parsing
