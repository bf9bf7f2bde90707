// The [validation] section (input/CaseSection.hpp): the analytic reference and its checks,
// the stability checks, and the refinement study.
#include "cmc/input/CaseSection.hpp"

#include <cmath>
#include <string>

namespace cmc::case_parsing {

namespace {

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

// Whether `path` ("section.key") names a number, or an array of numbers, of the case.
bool numeric_key(const toml::table& resolved, const std::string& path) {
  const auto dot = path.find('.');
  if (dot == std::string::npos || path.substr(0, dot) == "validation" || path.substr(0, dot) == "case") return false;
  const toml::node* n = resolved.at_path(path).node();
  if (!n) return false;
  if (n->is_number()) return true;
  const toml::array* a = n->as_array();
  if (!a || a->empty()) return false;
  for (const auto& e : *a)
    if (!e.is_number()) return false;
  return true;
}

// The continuity check's keys: what is changed, by how much, what is compared, and where not;
// the agreement check's: the other solver, what is compared, and where not.
void parse_continuity(Section& cs, const toml::table& resolved, StabilityCheck& ch) {
  if (ch.kind == StabilityKind::Agreement) {
    ch.solver = cs.choice<SolverKind>("solver");
  } else {
    ch.parameter = cs.string("parameter");
    if (!numeric_key(resolved, ch.parameter))
      cs.fail("parameter", "\"section.key\" naming a number or an array of numbers of this case (not of [case] or "
                           "[validation])");
    ch.change = cs.number("change", ch.change, "the relative change of the parameter", true);
  }
  ch.observable = cs.choice<PathObservable>("observable", ch.observable);
  ch.bound = cs.number("tolerance", {}, "the largest accepted relative change of the observable", true);
  if (cs.has("skip_steps"))
    for (double k : cs.numbers("skip_steps", "an array of load-step indices (steps across a documented jump)")) {
      if (k < 0 || k != std::floor(k) || k > double(CaseLimits::kMaxLoadSteps))
        cs.fail("skip_steps", "an array of load-step indices (steps across a documented jump)");
      ch.skip_steps.push_back(int(k));
    }
}

// The bound of each kind under its own key; kinds that are exact (same_bits,
// contact_fraction, pulloff) have none.
void parse_bound(Section& cs, StabilityCheck& ch) {
  using K = StabilityKind;
  switch (ch.kind) {
    case K::Iterations:
      ch.bound = double(cs.integer("budget", {}, "the most iterations a load step may take", 1,
                                   CaseLimits::kMaxIterations));
      break;
    case K::ResidualGrowth:
      ch.bound = cs.number("factor", {}, "the largest accepted growth of the residual within a solve (>= 1)", true);
      if (ch.bound < 1.0) cs.fail("factor", "the largest accepted growth of the residual within a solve (>= 1)");
      break;
    case K::EnergyRise:
    case K::Threads:
    case K::ForceBalance:
    case K::Gap:
      ch.bound = cs.number("tolerance", {}, "the largest accepted error (see cases/README.md)", false, true);
      break;
    case K::Hysteresis:
      ch.bound = cs.number("tolerance", 0.0, "the largest accepted loss of contact fraction on unloading", false, true);
      break;
    case K::SameBits:
    case K::ContactFraction:
    case K::Pulloff:
    case K::Continuity:
    case K::Agreement:
      break;
  }
}

StabilityCheck parse_stability(Section& cs, const toml::table& resolved) {
  StabilityCheck ch;
  ch.kind = cs.choice<StabilityKind>("kind");
  if (ch.kind == StabilityKind::Continuity || ch.kind == StabilityKind::Agreement) parse_continuity(cs, resolved, ch);
  else parse_bound(cs, ch);
  ch.expected_failure = cs.string("expected_failure", "");
  return ch;
}

}  // namespace

ValidationSpec parse_validation(Section s, const std::string& file, const toml::table& resolved) {
  ValidationSpec v;
  if (s.has("reference")) v.reference = s.choice<ValidationReference>("reference");
  if (auto* a = s.array("check")) {
    int i = 0;
    for (auto& e : *a) {
      if (!e.is_table()) s.fail("check", "an array of tables [[validation.check]]");
      Section cs(*e.as_table(), "validation.check #" + std::to_string(++i), file);
      if (cs.has("kind") == cs.has("quantity"))
        cs.fail(cs.has("kind") ? "quantity" : "kind",
                "either quantity (a comparison with the analytic reference) or kind (a stability check), not both");
      if (cs.has("kind")) {
        v.stability.push_back(parse_stability(cs, resolved));
      } else {
        if (!v.reference) s.fail("reference", "the analytic reference of the quantity checks");
        ValidationCheck ch;
        ch.quantity = cs.choice<ValidationQuantity>("quantity");
        ch.tolerance = cs.number("tolerance", {}, "the largest accepted error", true);
        v.checks.push_back(ch);
      }
      cs.finish();
    }
  }
  if (auto* r = s.subtable("refinement")) {
    if (!v.reference) s.fail("reference", "the analytic reference of the refinement study");
    v.refinement = parse_refinement(Section(*r, "validation.refinement", file));
  }
  if (v.checks.empty() && v.stability.empty() && !v.refinement)
    s.fail("check", "at least one [[validation.check]] or a [validation.refinement]");
  s.finish();
  return v;
}

}  // namespace cmc::case_parsing
