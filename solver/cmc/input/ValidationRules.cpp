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

void check_validation_fits(const Case& c) {
  if (!c.validation) return;
  const Ref r = c.validation->reference;
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
