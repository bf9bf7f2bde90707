#include "cmc/input/Case.hpp"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

namespace cmc {

namespace {

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
      got = ", got " + type_name(*n) + " " + s.str();
    }
    throw CaseError(file_ + ": " + key_name(key) + ": expected " + expected + got + where(n));
  }

  std::string string(const std::string& key, std::optional<std::string> def = {}, std::set<std::string> choices = {}) {
    used_.insert(key);
    const toml::node* n = t_->get(key);
    std::string expected = "a string";
    if (!choices.empty()) {
      expected = "one of";
      for (const auto& c : choices) expected += " \"" + c + "\"";
    }
    if (!n) {
      if (!def) fail_missing(key, expected);
      t_->insert(key, *def);
      return *def;
    }
    if (!n->is_string()) fail(key, expected);
    std::string v = n->as_string()->get();
    if (!choices.empty() && !choices.count(v)) fail(key, expected);
    return v;
  }

  double number(const std::string& key, std::optional<double> def, const std::string& what,
                bool positive = false, bool non_negative = false) {
    used_.insert(key);
    const toml::node* n = t_->get(key);
    if (!n) {
      if (!def) fail_missing(key, what);
      t_->insert(key, *def);
      return *def;
    }
    double v;
    if (auto f = n->as_floating_point()) v = f->get();
    else if (auto i = n->as_integer()) v = double(i->get());
    else fail(key, what);
    if (!std::isfinite(v)) fail(key, what + " (finite)");
    if (positive && !(v > 0.0)) fail(key, what + " (> 0)");
    if (non_negative && !(v >= 0.0)) fail(key, what + " (>= 0)");
    return v;
  }

  long long integer(const std::string& key, std::optional<long long> def, const std::string& what, long long min) {
    used_.insert(key);
    const toml::node* n = t_->get(key);
    if (!n) {
      if (!def) fail_missing(key, what);
      t_->insert(key, *def);
      return *def;
    }
    auto i = n->as_integer();
    if (!i) fail(key, what);
    if (i->get() < min) fail(key, what + " (>= " + std::to_string(min) + ")");
    return i->get();
  }

  bool boolean(const std::string& key, bool def) {
    used_.insert(key);
    const toml::node* n = t_->get(key);
    if (!n) {
      t_->insert(key, def);
      return def;
    }
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
    used_.insert(key);
    toml::node* n = t_->get(key);
    if (!n) return nullptr;
    if (!n->is_table()) fail(key, "a table");
    return n->as_table();
  }
  toml::array* array(const std::string& key) {
    used_.insert(key);
    toml::node* n = t_->get(key);
    if (!n) return nullptr;
    if (!n->is_array()) fail(key, "an array");
    return n->as_array();
  }
  void ignore(const std::string& key) { used_.insert(key); }

  // Every key not read is a mistake (a typo, or a key of another kind).
  void finish() const {
    for (const auto& [k, v] : *t_)
      if (!used_.count(std::string(k.str())))
        throw CaseError(file_ + ": " + key_name(std::string(k.str())) + ": unknown key" + where(&v) +
                        " (see cases/README.md for the keys of [" + name_ + "])");
  }

 private:
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
  if (eq == std::string::npos || eq == 0)
    throw CaseError("--set " + a + ": expected section.key=value");
  const std::string path = a.substr(0, eq), value = a.substr(eq + 1);
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
    c.description = s.string("description", std::string());
    s.finish();
  }
  {
    Section s(t, "grid", file, true);
    if (s.has("n")) {
      if (s.has("nx") || s.has("ny")) s.fail("n", "either n or nx/ny, not both");
      c.grid.nx = c.grid.ny = int(s.integer("n", {}, "a positive number of points per side", 1));
    } else {
      c.grid.nx = int(s.integer("nx", {}, "a positive number of points along x (or give n)", 1));
      c.grid.ny = int(s.integer("ny", {}, "a positive number of points along y (1 for a 1-D problem)", 1));
    }
    c.grid.size_x = s.number("size", {}, "the side length along x in m", true);
    c.grid.size_y = s.number("size_y", c.grid.size_x, "the side length along y in m", true);
    c.grid.periodic = s.string("boundary", std::string("periodic"), {"periodic", "free"}) == "periodic";
    const double points = double(c.grid.nx) * c.grid.ny;
    // A periodic solve holds about 8 fields of N doubles; free-boundary ones work on a
    // grid 4x larger. Refuse what cannot fit rather than failing deep in an allocation.
    const double bytes = points * 8.0 * (c.grid.periodic ? 8.0 : 20.0);
    if (bytes > 64e9) s.fail(c.grid.nx == c.grid.ny ? "n" : "nx", "a grid that fits in memory (this one needs about " +
                                                       std::to_string(int(bytes / 1e9)) + " GB)");
    if (!c.grid.periodic && c.grid.ny < 2) s.fail("ny", "at least 2 points: a free boundary needs a 2-D grid");
    s.finish();
  }
  {
    Section s(t, "material", file, true);
    c.contact_modulus = s.number("contact_modulus", {}, "the contact modulus E* in Pa", true);
    s.finish();
  }
  {
    Section s(t, "surface", file, true);
    auto& sf = c.surface;
    sf.kind = s.string("kind", {}, {"sphere", "wavy1d", "wavy2d", "flat", "self_affine", "file"});
    if (sf.kind == "sphere") {
      sf.radius = s.number("radius", {}, "the sphere radius in m", true);
      if (s.has("center")) {
        auto v = s.numbers("center", "[x, y] in m", 2);
        if (v.size() != 2) s.fail("center", "[x, y] in m");
        sf.center = v;
      }
    } else if (sf.kind == "wavy1d" || sf.kind == "wavy2d") {
      sf.amplitude = s.number("amplitude", {}, "the amplitude a in m of h = a (1 - cos(2 pi x / wavelength))", true);
      sf.wavelength = s.number("wavelength", c.grid.size_x, "the wavelength in m", true);
      const double periods = c.grid.size_x / sf.wavelength;
      if (c.grid.periodic && std::abs(periods - std::round(periods)) > 1e-9)
        s.fail("wavelength", "a wavelength that divides the periodic grid size " + std::to_string(c.grid.size_x));
    } else if (sf.kind == "self_affine") {
      if (c.grid.size_x != c.grid.size_y) s.fail("kind", "a square grid (size_y = size) for a self-affine surface");
      sf.hurst = s.number("hurst", 0.8, "the Hurst exponent H in (0, 1]", true);
      if (sf.hurst > 1.0) s.fail("hurst", "the Hurst exponent H in (0, 1]");
      sf.rolloff_wavelength = s.number("rolloff_wavelength", 0.2 * c.grid.size_x, "the roll-off wavelength in m", true);
      sf.cutoff_wavelength = s.number("cutoff_wavelength", 1e-3 * c.grid.size_x, "the short-wavelength cutoff in m", true);
      if (!(sf.cutoff_wavelength < sf.rolloff_wavelength) || sf.rolloff_wavelength > c.grid.size_x)
        s.fail("cutoff_wavelength", "cutoff_wavelength < rolloff_wavelength <= grid size");
      sf.rms_gradient = s.number("rms_gradient", 1.0, "the rms gradient of the surface", true);
      sf.seed = s.integer("seed", 28, "a non-negative random seed", 0);
    } else if (sf.kind == "file") {
      sf.path = s.string("path");
      sf.format = s.string("format", {}, {"challenge_hdf5", "challenge_ascii", "fourier", "hdf5", "ascii"});
      sf.dataset = s.string("dataset", std::string("surface"));
      // The challenge's own files hold heights in units of L; generic files say what they hold.
      const bool challenge = sf.format.rfind("challenge", 0) == 0 || sf.format == "fourier";
      sf.height_unit = s.number("height_unit", challenge ? c.grid.size_x : 1.0, "metres per height unit of the file", true);
    }
    s.finish();
  }
  {
    Section s(t, "interaction", file, false);
    auto& in = c.interaction;
    in.kind = s.string("kind", std::string("hard_wall"), {"hard_wall", "exponential", "dugdale"});
    if (in.kind != "hard_wall") {
      in.work_of_adhesion = s.number("work_of_adhesion", {}, "the work of adhesion in J/m^2", true);
      const bool sphere = c.surface.kind == "sphere", rough = c.surface.kind == "self_affine" || c.surface.kind == "file";
      int given = 0;
      if (s.has("range")) in.range = s.number("range", {}, "the interaction range in m", true), ++given;
      if (in.kind == "exponential" && s.has("tabor")) {
        if (!sphere && !rough) s.fail("tabor", "a sphere or rough surface (a radius of curvature to define mu_T); give range");
        in.tabor = s.number("tabor", {}, "the Tabor parameter mu_T", true), ++given;
      }
      if (in.kind == "dugdale" && s.has("maugis_lambda")) {
        if (!sphere) s.fail("maugis_lambda", "a sphere (Maugis' lambda needs its radius); give range");
        in.maugis_lambda = s.number("maugis_lambda", {}, "Maugis' parameter lambda", true), ++given;
      }
      if (given != 1)
        s.fail("range", in.kind == "exponential" ? "exactly one of range (m) or tabor"
                                                 : "exactly one of range (h0, m) or maugis_lambda");
      if (in.kind == "dugdale") in.smoothing = s.number("smoothing", 0.0, "a smoothing width in m", false, true);
    }
    s.finish();
  }
  {
    Section s(t, "loading", file, true);
    c.loading.control = s.string("control", {}, {"force", "mean_pressure", "penetration", "mean_gap"});
    const bool pressure_like = c.loading.control == "force" || c.loading.control == "mean_pressure";
    const std::string what = pressure_like ? "a non-empty array of loads (N or Pa)" : "a non-empty array of lengths in m";
    c.loading.values = s.numbers("values", what);
    if (s.has("unloading")) c.loading.unloading = s.numbers("unloading", what);
    if (pressure_like && c.interaction.kind == "hard_wall")
      for (const char* key : {"values", "unloading"})
        for (double v : key == std::string("values") ? c.loading.values : c.loading.unloading)
          if (v < 0.0) s.fail(key, "non-negative loads for a hard-wall (non-adhesive) contact");
    if (c.loading.control == "mean_gap" && !c.grid.periodic)
      s.fail("control", "\"force\" or \"penetration\": a mean gap needs a periodic grid");
    c.loading.max_halvings = int(s.integer("max_halvings", 5, "a non-negative number of halvings", 0));
    c.loading.jump_fraction = s.number("jump_fraction", 0.5, "a relative change that counts as a jump", true);
    c.loading.jump_pressure_floor =
        s.number("jump_pressure_floor", 0.0, "a pressure in Pa (0: the largest |mean pressure| so far)", false, true);
    c.loading.refine_pulloff = int(s.integer("refine_pulloff", 0, "a non-negative number of extra solves", 0));
    s.finish();
  }
  {
    Section s(t, "solver", file, false);
    const bool adhesive = c.interaction.kind != "hard_wall";
    c.solver.kind = s.string("kind", std::string(adhesive ? "adhesive_cg" : "polonsky_keer"), {"polonsky_keer", "adhesive_cg"});
    if (adhesive && c.solver.kind == "polonsky_keer")
      s.fail("kind", "\"adhesive_cg\": Polonsky-Keer solves hard-wall contact only");
    c.solver.tolerance = s.number("tolerance", c.solver.kind == "polonsky_keer" ? 1e-10 : 1e-8, "a relative residual", true);
    c.solver.max_iterations = int(s.integer("max_iterations", 2000, "a positive iteration cap", 1));
    c.solver.recompute_every = int(s.integer("recompute_every", 32, "a positive number of iterations", 1));
    s.finish();
  }
  {
    Section s(t, "output", file, false);
    c.write_fields = s.boolean("fields", true);
    s.finish();
  }
  {
    Section s(t, "observables", file, false);
    auto& o = c.observables;
    o.enabled = s.boolean("enabled", false);
    o.cross_section_x = s.number("cross_section_x", 0.5 * c.grid.size_x, "the x of the cross-section in m", false, true);
    o.stress_bins = int(s.integer("stress_bins", 100, "a positive number of bins", 1));
    o.gap_bins_per_decade = int(s.integer("gap_bins_per_decade", 10, "a positive number of bins", 1));
    o.patch_bins_per_decade = int(s.integer("patch_bins_per_decade", 5, "a positive number of bins", 1));
    o.contact_gap_threshold = s.number("contact_gap_threshold", 0.0, "a gap in m (0: contact where p > 0)", false, true);
    s.finish();
  }
  if (t.contains("validation")) {
    Section s(t, "validation", file, false);
    ValidationSpec v;
    v.reference = s.string("reference", {}, {"hertz", "hertz_periodic", "westergaard", "jkr", "maugis_dugdale",
                                             "johnson"});
    const std::set<std::string> quantities = {"penetration", "pressure_profile", "mean_pressure", "mean_gap", "force",
                                              "pulloff"};
    if (auto* a = s.array("check")) {
      int i = 0;
      for (auto& e : *a) {
        if (!e.is_table()) s.fail("check", "an array of tables [[validation.check]]");
        Section cs(*e.as_table(), "validation.check #" + std::to_string(++i), file);
        ValidationCheck ch;
        ch.quantity = cs.string("quantity", {}, quantities);
        ch.tolerance = cs.number("tolerance", {}, "the largest accepted error", true);
        cs.finish();
        v.checks.push_back(ch);
      }
    }
    if (auto* r = s.subtable("refinement")) {
      Section rs(*r, "validation.refinement", file);
      RefinementSpec ref;
      for (double g : rs.numbers("grids", "an increasing array of at least 2 grid sizes", 2)) {
        if (g < 2 || g != std::floor(g) || (!ref.grids.empty() && g <= ref.grids.back()))
          rs.fail("grids", "an increasing array of at least 2 grid sizes");
        ref.grids.push_back(int(g));
      }
      ref.quantity = rs.string("quantity", {}, quantities);
      ref.min_order = rs.number("min_order", {}, "the smallest accepted observed order of convergence", true);
      rs.finish();
      v.refinement = ref;
    }
    if (v.checks.empty() && !v.refinement) s.fail("check", "at least one [[validation.check]] or a [validation.refinement]");
    s.finish();
    c.validation = v;
  }
  return c;
}

Case load_case(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path);
  if (!in) throw CaseError(path + ": cannot open the case file");
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
