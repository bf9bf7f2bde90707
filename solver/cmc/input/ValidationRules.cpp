#include "cmc/input/ValidationRules.hpp"

#include <initializer_list>
#include <string_view>
#include <string>
#include <vector>

namespace cmc {

namespace {

using Ref = ValidationReference;
using Q = ValidationQuantity;

// One row of the table in ValidationRules.hpp.
struct Fits {
  SurfaceKind surface;
  std::vector<InteractionKind> interactions;
  bool periodic_only;
  std::vector<Q> quantities;
};

Fits fits(Ref r) {
  using S = SurfaceKind;
  using I = InteractionKind;
  switch (r) {
    case Ref::Hertz: return {S::Sphere, {I::HardWall}, false, {Q::Penetration, Q::PressureProfile}};
    case Ref::HertzPeriodic: return {S::Sphere, {I::HardWall}, true, {Q::Penetration, Q::PressureProfile}};
    case Ref::Westergaard:
      return {S::Wavy1d, {I::HardWall}, true, {Q::MeanPressure, Q::PressureProfile, Q::MeanGap}};
    case Ref::Jkr: return {S::Sphere, {I::Exponential}, false, {Q::Force, Q::Pulloff}};
    case Ref::MaugisDugdale: return {S::Sphere, {I::Dugdale}, false, {Q::Force, Q::Pulloff}};
    case Ref::Johnson:
      return {S::Wavy1d, {I::Exponential, I::Dugdale}, true, {Q::MeanPressure, Q::MeanGap, Q::Pulloff}};
  }
  return {};
}

// A case-file word in quotes (appended, not "\"" + ...: GCC 12 warns falsely of the latter).
std::string quoted(std::string_view word) {
  std::string q(1, '"');
  q.append(word).push_back('"');
  return q;
}

template <class E>
std::string words(const std::vector<E>& values, const char* joint) {
  std::string s;
  for (std::size_t k = 0; k < values.size(); ++k)
    s += (k == 0 ? "" : k + 1 == values.size() ? joint : ", ") + quoted(kind_name(values[k]));
  return s;
}

}  // namespace

namespace {

// What a stability check needs of the case: an energy the solver reports, a load path with a
// pull-off, unloading steps to compare, another solver that can solve it.
void check_stability_fits(const Case& c) {
  int i = 0;
  for (const StabilityCheck& ch : c.validation->stability) {
    const std::string key = "[validation.check #" + std::to_string(++i) + "] kind";
    auto refuse = [&](const std::string& needs) {
      throw CaseError(c.file + ": " + key + " = " + quoted(kind_name(ch.kind)) + ": expected a case with " + needs);
    };
    const bool adhesive_cg = c.solver.kind == SolverKind::AdhesiveCg;
    if (ch.kind == StabilityKind::EnergyRise && !adhesive_cg)
      refuse("[solver] kind = \"adhesive_cg\" (the solver that reports its energy at every iteration)");
    if (ch.kind == StabilityKind::Pulloff && !adhesive_cg)
      refuse("[solver] kind = \"adhesive_cg\" (the load path that records a pull-off)");
    if (ch.kind == StabilityKind::Hysteresis && c.loading.unloading.empty())
      refuse("[loading] unloading steps (to compare with the loading branch at the same load)");
    if (ch.kind == StabilityKind::Agreement && (ch.solver == c.solver.kind || ch.solver == SolverKind::Auto))
      refuse("another solver than its own in `solver` (this case runs " + quoted(kind_name(c.solver.kind)) + ")");
    if (ch.kind == StabilityKind::Agreement && ch.solver == SolverKind::QuasiStatic &&
        c.interaction.kind != InteractionKind::Exponential)
      refuse("[interaction] kind = \"exponential\" for the quasi-static solver");
    if (ch.kind == StabilityKind::Agreement && ch.solver == SolverKind::PolonskyKeer &&
        c.interaction.kind != InteractionKind::HardWall)
      refuse("[interaction] kind = \"hard_wall\" for Polonsky-Keer");
  }
}

}  // namespace

void check_validation_fits(const Case& c) {
  if (!c.validation) return;
  check_stability_fits(c);
  if (!c.validation->reference) return;
  const Ref r = *c.validation->reference;
  const Fits f = fits(r);
  const std::string ref = quoted(kind_name(r));
  const std::string what = ref + " compares a " + std::string(kind_name(f.surface)) + " surface with " +
                           words(f.interactions, " or ") + " interaction" + (f.periodic_only ? " on a periodic grid" : "");
  auto refuse = [&](const std::string& got) {
    throw CaseError(c.file + ": [validation] reference: " + what + "; expected a reference for this case, which has " +
                    got + " (the references and what they compare: cases/README.md, [validation])");
  };
  if (c.surface.kind != f.surface) refuse("[surface] kind = " + quoted(kind_name(c.surface.kind)));
  bool interaction = false;
  for (InteractionKind k : f.interactions) interaction |= k == c.interaction.kind;
  if (!interaction) refuse("[interaction] kind = " + quoted(kind_name(c.interaction.kind)));
  if (f.periodic_only && !c.grid.periodic) refuse("[grid] boundary = \"free\"");
  auto quantity = [&](Q q, const std::string& key) {
    for (Q k : f.quantities)
      if (k == q) return;
    throw CaseError(c.file + ": " + key + ": expected " + words(f.quantities, " or ") + " (what reference " + ref +
                    " has), got " + quoted(kind_name(q)));
  };
  int i = 0;
  for (const ValidationCheck& ch : c.validation->checks)
    quantity(ch.quantity, "[validation.check #" + std::to_string(++i) + "] quantity");
  if (c.validation->refinement) quantity(c.validation->refinement->quantity, "[validation.refinement] quantity");
}

}  // namespace cmc
