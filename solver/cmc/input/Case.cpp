#include "cmc/input/Case.hpp"

#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <set>
#include <sstream>

namespace cmc {

namespace {

// A number as cases/README.md writes it: the shortest form that reads back the same.
std::string number_text(double v) {
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
std::string where(const toml::node* n) {
  if (!n) return "";
  const auto& s = n->source();
  if (!s.begin) return "";
  return " (line " + std::to_string(s.begin.line) + ")";
}

std::string type_name(const toml::node& n) {
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

const std::set<std::string> kSections = {"case", "grid", "material", "surface", "interaction", "loading",
                                         "solver", "output", "observables", "validation"};

}  // namespace

void apply_override(toml::table& t, const std::string& a) {
  const auto eq = a.find('=');
  if (eq == std::string::npos || a.find_first_not_of(" \t") == eq)
    throw CaseError("--set " + a + ": expected section.key=value");
  // Spaces around the key and the '=' are allowed, as in a TOML file: 'grid.n = 64'.
  std::string path = a.substr(0, eq), value = a.substr(eq + 1);
  path.erase(path.find_last_not_of(" \t") + 1).erase(0, std::min(path.find_first_not_of(" \t"), path.size()));
  value.erase(0, std::min(value.find_first_not_of(" \t"), value.size()));
  const auto dot = path.rfind('.');
  if (dot == std::string::npos)
    throw CaseError("--set " + a + ": expected section.key=value (the key needs its section)");
  toml::node_view<toml::node> sect = t.at_path(path.substr(0, dot));
  if (!sect) {
    t.insert(path.substr(0, dot), toml::table{});
    sect = t.at_path(path.substr(0, dot));
  }
  if (!sect.is_table()) throw CaseError("--set " + a + ": " + path.substr(0, dot) + " is not a table");
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + value);
  } catch (const toml::parse_error&) {
    parsed.insert("v", value);  // a bare word: take it as a string
  }
  sect.as_table()->insert_or_assign(path.substr(dot + 1), *parsed.get("v"));
}

namespace {

// Whether this build has the CUDA backend (grid/Backend.hpp; CMakeLists.txt defines CMC_CUDA).
#ifdef CMC_CUDA
constexpr bool kCudaBuilt = true;
#else
constexpr bool kCudaBuilt = false;
#endif

void parse_grid(Section s, GridSpec& g) {
  // Sizes are bounded before they are narrowed to int (a larger one would wrap); whether
  // the grid fits in memory is checked once the whole case is known (check_memory).
  constexpr long long side = CaseLimits::kMaxGridSide;
  if (s.has("n")) {
    if (s.has("nx") || s.has("ny")) s.fail("n", "either n or nx/ny, not both");
    g.nx = g.ny = int(s.integer("n", {}, "a positive number of points per side", 1, side));
  } else {
    g.nx = int(s.integer("nx", {}, "a positive number of points along x (or give n)", 1, side));
    g.ny = int(s.integer("ny", {}, "a positive number of points along y (1 for a 1-D problem)", 1, side));
  }
  g.size_x = s.number("size", {}, "the side length along x in m", true);
  g.size_y = s.number("size_y", g.size_x, "the side length along y in m", true);
  g.periodic = s.string("boundary", std::string(g.periodic ? "periodic" : "free"), {"periodic", "free"}) == "periodic";
  if (!g.periodic && g.ny < 2) s.fail("ny", "at least 2 points: a free boundary needs a 2-D grid");
  g.backend = s.string("backend", g.backend, {"cpu", "cuda"});
  if (g.backend == "cuda" && !kCudaBuilt)
    s.fail("backend", "\"cpu\": this build of cmc has no CUDA backend (configure a build folder with -DCMC_CUDA=ON; "
                      "README, \"GPU\")");
  if (g.backend == "cuda" && !g.periodic)
    s.fail("backend", "\"cpu\" with boundary = \"free\": the CUDA backend has the periodic boundary only");
  s.finish();
}

void parse_surface(Section s, const GridSpec& grid, SurfaceSpec& sf) {
  sf.kind = s.choice<SurfaceKind>("kind");
  switch (sf.kind) {
    case SurfaceKind::Sphere:
      sf.radius = s.number("radius", {}, "the sphere radius in m", true);
      if (s.has("center")) {
        auto v = s.numbers("center", "[x, y] in m", 2);
        if (v.size() != 2) s.fail("center", "[x, y] in m");
        sf.center = v;
      }
      break;
    case SurfaceKind::Wavy1d:
    case SurfaceKind::Wavy2d: {
      sf.amplitude = s.number("amplitude", {}, "the amplitude a in m of h = a (1 - cos(2 pi x / wavelength))", true);
      sf.wavelength = s.number("wavelength", grid.size_x, "the wavelength in m", true);
      const double periods = grid.size_x / sf.wavelength;
      if (grid.periodic && std::abs(periods - std::round(periods)) > 1e-9)
        s.fail("wavelength", "a wavelength that divides the periodic grid size " + std::to_string(grid.size_x));
      break;
    }
    case SurfaceKind::SelfAffine:
      if (grid.size_x != grid.size_y) s.fail("kind", "a square grid (size_y = size) for a self-affine surface");
      if (grid.nx < 2 || grid.ny < 2)
        s.fail("kind", "a grid of at least 2 x 2 points for a self-affine surface ([grid] n = " +
                           std::to_string(std::min(grid.nx, grid.ny)) + " here)");
      sf.hurst = s.number("hurst", sf.hurst, "the Hurst exponent H in (0, 1]", true);
      if (sf.hurst > 1.0) s.fail("hurst", "the Hurst exponent H in (0, 1]");
      sf.rolloff_wavelength = s.number("rolloff_wavelength", SurfaceSpec::kRolloffFraction * grid.size_x,
                                       "the roll-off wavelength in m", true);
      sf.cutoff_wavelength = s.number("cutoff_wavelength", SurfaceSpec::kCutoffFraction * grid.size_x,
                                      "the short-wavelength cutoff in m", true);
      if (!(sf.cutoff_wavelength < sf.rolloff_wavelength) || sf.rolloff_wavelength > grid.size_x)
        s.fail("cutoff_wavelength", "cutoff_wavelength < rolloff_wavelength <= grid size");
      // The whole band is generated whatever the grid: (pi/2) (size/cutoff)^2 modes.
      if (grid.size_x / sf.cutoff_wavelength > CaseLimits::kMaxBandRatio)
        s.fail("cutoff_wavelength", "at least 1e-6 x the grid size, " + number_text(grid.size_x * 1e-6) +
                                        " m (the generator makes every mode of the band, whatever the grid)");
      sf.rms_gradient = s.number("rms_gradient", sf.rms_gradient, "the rms gradient of the surface", true);
      sf.seed = s.integer("seed", sf.seed, "a non-negative random seed", 0, CaseLimits::kMaxSeed);
      break;
    case SurfaceKind::File: {
      sf.path = s.string("path");
      sf.format = s.choice<SurfaceFormat>("format");
      sf.dataset = s.string("dataset", sf.dataset);
      // The challenge's own files hold heights in units of L; generic files say what they hold.
      const bool in_units_of_l = sf.format == SurfaceFormat::ChallengeHdf5 ||
                                 sf.format == SurfaceFormat::ChallengeAscii || sf.format == SurfaceFormat::Fourier;
      sf.height_unit = s.number("height_unit", in_units_of_l ? grid.size_x : 1.0, "metres per height unit of the file", true);
      break;
    }
    case SurfaceKind::Flat:
      break;
  }
  const std::string wavy = "kind = \"wavy1d\" or \"wavy2d\"", rough = "kind = \"self_affine\"", file = "kind = \"file\"";
  s.finish({{"radius", "kind = \"sphere\""}, {"center", "kind = \"sphere\""}, {"amplitude", wavy}, {"wavelength", wavy},
            {"hurst", rough}, {"rolloff_wavelength", rough}, {"cutoff_wavelength", rough}, {"rms_gradient", rough},
            {"seed", rough}, {"path", file}, {"format", file}, {"dataset", file}, {"height_unit", file}});
}

void parse_interaction(Section s, SurfaceKind surface, InteractionSpec& in) {
  in.kind = s.choice<InteractionKind>("kind", in.kind);
  if (in.kind != InteractionKind::HardWall) {
    const bool exponential = in.kind == InteractionKind::Exponential;
    in.work_of_adhesion = s.number("work_of_adhesion", {}, "the work of adhesion in J/m^2", true);
    const bool sphere = surface == SurfaceKind::Sphere;
    const bool rough = surface == SurfaceKind::SelfAffine || surface == SurfaceKind::File;
    int given = 0;
    if (s.has("range")) in.range = s.number("range", {}, "the interaction range in m", true), ++given;
    if (exponential && s.has("tabor")) {
      if (!sphere && !rough) s.fail("tabor", "a sphere or rough surface (a radius of curvature to define mu_T); give range");
      in.tabor = s.number("tabor", {}, "the Tabor parameter mu_T", true), ++given;
    }
    if (!exponential && s.has("maugis_lambda")) {
      if (!sphere) s.fail("maugis_lambda", "a sphere (Maugis' lambda needs its radius); give range");
      in.maugis_lambda = s.number("maugis_lambda", {}, "Maugis' parameter lambda", true), ++given;
    }
    if (given != 1)
      s.fail("range", exponential ? "exactly one of range (m) or tabor" : "exactly one of range (h0, m) or maugis_lambda");
    if (!exponential) in.smoothing = s.number("smoothing", in.smoothing, "a smoothing width in m", false, true);
    if (s.has("coarse_graining")) {
      if (!exponential) s.fail("coarse_graining", "kind = \"exponential\" (Dugdale's law has its own smoothing)");
      in.coarse_graining = s.choice<CoarseGraining>("coarse_graining", in.coarse_graining);
    }
  }
  const std::string adhesive = "kind = \"exponential\" or \"dugdale\"";
  s.finish({{"work_of_adhesion", adhesive}, {"range", adhesive}, {"tabor", "kind = \"exponential\""},
            {"coarse_graining", "kind = \"exponential\""}, {"maugis_lambda", "kind = \"dugdale\""},
            {"smoothing", "kind = \"dugdale\""}});
}

void parse_loading(Section s, bool adhesive, bool periodic, LoadingSpec& l) {
  l.control = s.choice<LoadControl>("control");
  const bool pressure_like = l.control == LoadControl::Force || l.control == LoadControl::MeanPressure;
  const std::string what = pressure_like ? "a non-empty array of loads (N or Pa)" : "a non-empty array of lengths in m";
  l.values = s.numbers("values", what);
  if (s.has("unloading")) l.unloading = s.numbers("unloading", what);
  if (l.values.size() + l.unloading.size() > CaseLimits::kMaxLoadSteps)
    s.fail(l.unloading.empty() ? "values" : "unloading",
           "at most " + std::to_string(CaseLimits::kMaxLoadSteps) + " load steps in values and unloading together (got " +
               std::to_string(l.values.size() + l.unloading.size()) + ")");
  if (pressure_like && !adhesive)
    for (const char* key : {"values", "unloading"})
      for (double v : key == std::string("values") ? l.values : l.unloading)
        if (v < 0.0) s.fail(key, "non-negative loads for a hard-wall (non-adhesive) contact");
  if (l.control == LoadControl::MeanGap && !periodic)
    s.fail("control", "\"force\" or \"penetration\": a mean gap needs a periodic grid");
  // Bounded: a step that still fails at the finest level is walked in 2^max_halvings sub-steps.
  l.max_halvings = int(s.integer("max_halvings", l.max_halvings, "a non-negative number of halvings", 0,
                                 CaseLimits::kMaxHalvings));
  l.jump_fraction = s.number("jump_fraction", l.jump_fraction, "a relative change that counts as a jump", true);
  l.jump_pressure_floor = s.number("jump_pressure_floor", l.jump_pressure_floor,
                                   "a pressure in Pa (0: the largest |mean pressure| so far)", false, true);
  l.refine_pulloff = int(s.integer("refine_pulloff", l.refine_pulloff, "a non-negative number of extra solves", 0,
                                   CaseLimits::kMaxRefinePulloff));
  s.finish();
}

// A loading path: the load grows (the mean gap shrinks) from each value to the next, and
// nothing is unloaded. The quasi-static solver follows only such paths.
bool loading_only(const LoadingSpec& l) {
  if (!l.unloading.empty()) return false;
  for (std::size_t k = 1; k < l.values.size(); ++k) {
    const bool grows = l.control == LoadControl::MeanGap ? l.values[k] <= l.values[k - 1] : l.values[k] >= l.values[k - 1];
    if (!grows) return false;
  }
  return true;
}

// "auto" picks the solver that can solve the interaction and the path; a solver that
// cannot is an error naming the key. The resolved case records the solver that runs.
void parse_solver(Section s, const InteractionSpec& in, const LoadingSpec& l, SolverSpec& sv) {
  const bool adhesive = in.kind != InteractionKind::HardWall;
  const bool exponential = in.kind == InteractionKind::Exponential;
  sv.kind = s.choice<SolverKind>("kind", sv.kind);
  if (sv.kind == SolverKind::Auto)
    sv.kind = !adhesive                         ? SolverKind::PolonskyKeer
              : exponential && loading_only(l) ? SolverKind::QuasiStatic
                                               : SolverKind::AdhesiveCg;
  if (adhesive && sv.kind == SolverKind::PolonskyKeer)
    s.fail("kind", "\"adhesive_cg\", \"quasi_static\" or \"auto\" with an adhesive interaction (Polonsky-Keer solves "
                   "hard-wall contact only)");
  if (sv.kind == SolverKind::QuasiStatic && !exponential)
    s.fail("kind", "\"adhesive_cg\" or \"auto\": \"quasi_static\" needs [interaction] kind = \"exponential\"");
  if (sv.kind == SolverKind::QuasiStatic && !loading_only(l))
    s.fail("kind", "\"adhesive_cg\" or \"auto\": \"quasi_static\" follows a loading path only ([loading] values in "
                   "the loading direction, no unloading)");
  s.resolve("kind", std::string(kind_name(sv.kind)));
  const bool pk = sv.kind == SolverKind::PolonskyKeer;
  sv.tolerance = s.number("tolerance", pk ? SolverSpec::kPolonskyKeerTolerance : SolverSpec::kAdhesiveTolerance,
                          "a relative residual", true);
  if (sv.tolerance > CaseLimits::kMaxSolverTolerance)
    s.fail("tolerance", "a relative residual of at most " + number_text(CaseLimits::kMaxSolverTolerance) +
                            " (a looser one stops a solve after a few iterations, far from the answer)");
  sv.max_iterations =
      int(s.integer("max_iterations", sv.max_iterations, "a positive iteration cap", 1, CaseLimits::kMaxIterations));
  sv.recompute_every = int(
      s.integer("recompute_every", sv.recompute_every, "a positive number of iterations", 1, CaseLimits::kMaxIterations));
  sv.tension_tolerance = s.number("tension_tolerance", sv.tension_tolerance,
                                  "a relative change of the adhesive tension (quasi_static)", true);
  sv.max_outer_steps = int(s.integer("max_outer_steps", sv.max_outer_steps,
                                     "a positive number of outer steps (quasi_static)", 1, CaseLimits::kMaxIterations));
  sv.max_seconds = s.number("max_seconds", sv.max_seconds,
                             "seconds a load step's solve may take (quasi_static), 0 for no limit", false, true);
  sv.precondition = s.boolean("precondition", sv.precondition);
  s.finish();
}

void parse_observables(Section s, double size_x, ObservablesSpec& o) {
  o.enabled = s.boolean("enabled", o.enabled);
  o.cross_section_x = s.number("cross_section_x", ObservablesSpec::kCrossSectionFraction * size_x,
                               "the x of the cross-section in m", false, true);
  // Inside the cell: a larger x would be wrapped around the period without a word.
  if (!(o.cross_section_x < size_x))
    s.fail("cross_section_x", "an x inside the cell, 0 <= x < size = " + number_text(size_x) + " m");
  o.stress_bins =
      int(s.integer("stress_bins", o.stress_bins, "a positive number of bins", 1, CaseLimits::kMaxStressBins));
  o.gap_bins_per_decade = int(s.integer("gap_bins_per_decade", o.gap_bins_per_decade, "a positive number of bins", 1,
                                        CaseLimits::kMaxBinsPerDecade));
  o.patch_bins_per_decade = int(s.integer("patch_bins_per_decade", o.patch_bins_per_decade,
                                          "a positive number of bins", 1, CaseLimits::kMaxBinsPerDecade));
  o.contact_gap_threshold = s.number("contact_gap_threshold", o.contact_gap_threshold,
                                     "a gap in m (a point is in contact where g <= this)", false, true);
  s.finish();
}

// The case name becomes a folder name (cmc validate --out DIR/<name>/): one path
// component, short enough for every file system, that cannot climb out of DIR.
void check_name(Section& s, const std::string& name) {
  const std::string what = "a name usable as one folder name";
  if (name.empty()) s.fail("name", what + " (not empty)");
  if (name.size() > CaseLimits::kMaxNameBytes)
    s.fail("name", what + " of at most " + std::to_string(CaseLimits::kMaxNameBytes) + " bytes (this one has " +
                       std::to_string(name.size()) + ")");
  for (unsigned char ch : name)
    if (ch == '/' || ch == '\\' || ch < 0x20 || ch == 0x7f)
      s.fail("name", what + ": no '/', '\\' or control characters");
  if (name.front() == '.') s.fail("name", what + ": not starting with '.' (no '.', '..' or hidden folders)");
}

// The grid of the case, and every grid its refinement study runs, must fit in the
// memory this machine has now: checked before anything is allocated.
void check_memory(const Case& c, toml::table& t, const std::string& file) {
  std::optional<double> avail = available_memory();
  if (!avail) return;
  *avail /= double(memory_split().ranks_here);  // a distributed run's ranks share the machine's memory
  auto too_big = [&](const Case& run) {
    const MemoryEstimate e = estimate_memory(run);
    if (e.bytes <= *avail) return std::string();
    return "a grid whose run fits in the memory available: a run on " + std::to_string(run.grid.nx) + " x " +
           std::to_string(run.grid.ny) + " points holds about " + memory_text(e.bytes) + " (" + e.what + "), and " +
           memory_text(*avail) + " is available";
  };
  Section grid(*t["grid"].as_table(), "grid", file);
  if (const std::string m = too_big(c); !m.empty()) grid.fail(grid.has("n") ? "n" : "nx", m);
  if (c.validation && c.validation->refinement) {
    Case finest = c;  // as run_refinement sets it: a 1-D case refines along x only
    finest.grid.nx = c.validation->refinement->grids.back();
    if (grid.has("n") || c.grid.ny > 1) finest.grid.ny = finest.grid.nx;
    if (const std::string m = too_big(finest); !m.empty())
      Section(*t["validation"]["refinement"].as_table(), "validation.refinement", file).fail("grids", m);
  }
}

RefinementSpec parse_refinement(Section rs) {
  RefinementSpec ref;
  const std::string what = "an increasing array of at least 2 grid sizes, each from 2 to " +
                           std::to_string(CaseLimits::kMaxGridSide);
  for (double g : rs.numbers("grids", what, 2)) {
    if (g < 2 || g > double(CaseLimits::kMaxGridSide) || g != std::floor(g) ||
        (!ref.grids.empty() && g <= ref.grids.back()))
      rs.fail("grids", what);
    ref.grids.push_back(int(g));
  }
  ref.quantity = rs.choice<ValidationQuantity>("quantity");
  ref.min_order = rs.number("min_order", {}, "the smallest accepted observed order of convergence", true);
  rs.finish();
  return ref;
}

ValidationSpec parse_validation(Section s, const std::string& file) {
  ValidationSpec v;
  v.reference = s.choice<ValidationReference>("reference");
  if (auto* a = s.array("check")) {
    int i = 0;
    for (auto& e : *a) {
      if (!e.is_table()) s.fail("check", "an array of tables [[validation.check]]");
      Section cs(*e.as_table(), "validation.check #" + std::to_string(++i), file);
      ValidationCheck ch;
      ch.quantity = cs.choice<ValidationQuantity>("quantity");
      ch.tolerance = cs.number("tolerance", {}, "the largest accepted error", true);
      cs.finish();
      v.checks.push_back(ch);
    }
  }
  if (auto* r = s.subtable("refinement")) v.refinement = parse_refinement(Section(*r, "validation.refinement", file));
  if (v.checks.empty() && !v.refinement) s.fail("check", "at least one [[validation.check]] or a [validation.refinement]");
  s.finish();
  return v;
}

}  // namespace

Case parse_case(const toml::table& input, const std::string& file) {
  Case c;
  c.file = file;
  c.resolved = input;
  toml::table& t = c.resolved;
  for (const auto& [k, v] : t)
    if (!kSections.count(std::string(k.str())))
      throw CaseError(file + ": [" + std::string(k.str()) + "]: unknown section" + where(&v) +
                      " (expected one of [case] [grid] [material] [surface] [interaction] [loading] [solver] "
                      "[output] [observables] [validation])");
  {
    Section s(t, "case", file, true);
    c.name = s.string("name");
    check_name(s, c.name);
    c.description = s.string("description", c.description);
    if (c.description.size() > CaseLimits::kMaxDescriptionBytes)
      s.fail("description", "one line of at most " + std::to_string(CaseLimits::kMaxDescriptionBytes) + " bytes");
    s.finish();
  }
  parse_grid(Section(t, "grid", file, true), c.grid);
  {
    Section s(t, "material", file, true);
    c.contact_modulus = s.number("contact_modulus", {}, "the contact modulus E* in Pa", true);
    s.finish();
  }
  parse_surface(Section(t, "surface", file, true), c.grid, c.surface);
  parse_interaction(Section(t, "interaction", file, false), c.surface.kind, c.interaction);
  const bool adhesive = c.interaction.kind != InteractionKind::HardWall;
  parse_loading(Section(t, "loading", file, true), adhesive, c.grid.periodic, c.loading);
  parse_solver(Section(t, "solver", file, false), c.interaction, c.loading, c.solver);
  if (c.grid.backend == "cuda" && c.solver.kind == SolverKind::AdhesiveCg)
    Section(t, "grid", file, true)
        .fail("backend", "\"cpu\" with [solver] kind = \"adhesive_cg\": the CUDA backend runs the polonsky_keer and "
                         "quasi_static solvers (hard wall; exponential adhesion on a loading path)");
  {
    Section s(t, "output", file, false);
    c.write_fields = s.boolean("fields", c.write_fields);
    s.finish();
  }
  parse_observables(Section(t, "observables", file, false), c.grid.size_x, c.observables);
  if (t.contains("validation")) c.validation = parse_validation(Section(t, "validation", file, false), file);
  check_memory(c, t, file);
  return c;
}

namespace {
std::string quoted_word(std::string_view word) {
  std::string q(1, '"');
  q.append(word).push_back('"');
  return q;
}
}  // namespace

std::vector<DocumentedDefault> case_defaults() {
  const GridSpec g;
  const SurfaceSpec sf;
  const InteractionSpec in;
  const LoadingSpec l;
  const SolverSpec sv;
  const ObservablesSpec o;
  const Case c;
  const auto n = [](double v) { return number_text(v); };
  const auto b = [](bool v) { return std::string(v ? "true" : "false"); };
  const std::string req = "required";
  return {
      {"case", "name", req},
      {"case", "description", quoted_word(c.description)},
      {"grid", "n", "—"},
      {"grid", "nx", "—"},
      {"grid", "ny", "—"},
      {"grid", "size", req},
      {"grid", "size_y", "size"},
      {"grid", "boundary", quoted_word(g.periodic ? "periodic" : "free")},
      {"grid", "backend", quoted_word(g.backend)},
      {"material", "contact_modulus", req},
      {"surface", "kind", req},
      {"surface", "radius", "required for sphere"},
      {"surface", "center", "box centre"},
      {"surface", "amplitude", "required for wavy*"},
      {"surface", "wavelength", "grid.size"},
      {"surface", "hurst", n(sf.hurst)},
      {"surface", "rolloff_wavelength", n(SurfaceSpec::kRolloffFraction) + " size"},
      {"surface", "cutoff_wavelength", n(SurfaceSpec::kCutoffFraction) + " size"},
      {"surface", "rms_gradient", n(sf.rms_gradient)},
      {"surface", "seed", n(double(sf.seed))},
      {"surface", "path", "required for file"},
      {"surface", "format", "required for file"},
      {"surface", "dataset", quoted_word(sf.dataset)},
      {"surface", "height_unit", "size for challenge formats, else 1"},
      {"interaction", "kind", quoted_word(kind_name(in.kind))},
      {"interaction", "work_of_adhesion", "required for adhesion"},
      {"interaction", "range", "one of three"},
      {"interaction", "tabor", "one of three"},
      {"interaction", "maugis_lambda", "one of three"},
      {"interaction", "smoothing", n(in.smoothing)},
      {"interaction", "coarse_graining", quoted_word(kind_name(in.coarse_graining))},
      {"loading", "control", req},
      {"loading", "values", req},
      {"loading", "unloading", "[]"},
      {"loading", "max_halvings", n(l.max_halvings)},
      {"loading", "jump_fraction", n(l.jump_fraction)},
      {"loading", "jump_pressure_floor", n(l.jump_pressure_floor)},
      {"loading", "refine_pulloff", n(l.refine_pulloff)},
      {"solver", "kind", quoted_word(kind_name(sv.kind))},
      {"solver", "tolerance",
       n(SolverSpec::kPolonskyKeerTolerance) + " PK, " + n(SolverSpec::kAdhesiveTolerance) + " adhesive"},
      {"solver", "max_iterations", n(sv.max_iterations)},
      {"solver", "recompute_every", n(sv.recompute_every)},
      {"solver", "tension_tolerance", n(sv.tension_tolerance)},
      {"solver", "max_outer_steps", n(sv.max_outer_steps)},
      {"solver", "max_seconds", n(sv.max_seconds)},
      {"solver", "precondition", b(sv.precondition)},
      {"output", "fields", b(c.write_fields)},
      {"observables", "enabled", b(o.enabled)},
      {"observables", "cross_section_x", n(ObservablesSpec::kCrossSectionFraction) + " size"},
      {"observables", "stress_bins", n(o.stress_bins)},
      {"observables", "gap_bins_per_decade", n(o.gap_bins_per_decade)},
      {"observables", "patch_bins_per_decade", n(o.patch_bins_per_decade)},
      {"observables", "contact_gap_threshold", n(o.contact_gap_threshold)},
  };
}

// ---------------------------------------------------------------- reading

Case load_case(const std::string& path, const std::vector<std::string>& overrides) {
  // A case file is a regular file of bounded size: a folder or a pipe would otherwise
  // read as an empty case ("missing required section [case]"), and its folder anchors
  // the relative paths in it.
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (!fs::exists(st)) throw CaseError(path + ": cannot open the case file: no such file");
  if (fs::is_directory(st)) throw CaseError(path + ": is a folder, expected a case file (TOML)");
  if (!fs::is_regular_file(st))
    throw CaseError(path + ": is not a regular file (a pipe, terminal or device), expected a case file (TOML) on disk");
  if (const auto size = fs::file_size(path, ec); !ec && size > CaseLimits::kMaxCaseFileBytes)
    throw CaseError(path + ": is " + memory_text(double(size)) + ", expected a case file (TOML) of at most " +
                    memory_text(double(CaseLimits::kMaxCaseFileBytes)));
  std::ifstream in(path);
  if (!in) throw CaseError(path + ": cannot open the case file (not readable)");
  toml::table t;
  try {
    t = toml::parse(in, path);
  } catch (const toml::parse_error& e) {
    std::ostringstream s;
    s << path << ": not valid TOML at line " << e.source().begin.line << ", column " << e.source().begin.column
      << ": " << e.description();
    throw CaseError(s.str());
  }
  for (const auto& o : overrides) apply_override(t, o);
  return parse_case(t, path);
}

}  // namespace cmc
