// A case table parsed and validated into a Case (Case.hpp): the sections in order, each by
// its parser (input/CaseSections.cpp), then the checks that need the whole case.
#include "cmc/input/CaseSection.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>

namespace cmc {

using namespace case_parsing;

namespace {

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
  if (t.contains("validation")) c.validation = parse_validation(Section(t, "validation", file, false), file, t);
  check_memory(c, t, file);
  return c;
}

}  // namespace cmc
