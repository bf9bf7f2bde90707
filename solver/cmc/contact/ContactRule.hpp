// What "in contact" means, defined once for all of cmc: the load path's jump test, the
// contact_fraction of every step record, the observables (fractions, contact mask,
// patches, perimeter) and the validation harness all use this rule.
//
//   in contact           g <= contact_gap   (a closed gap; contact_gap = 0 unless the
//                                            case sets [observables] contact_gap_threshold)
//   repulsive contact    p >  stress_cut    (compressive)
//   attractive contact   p < -stress_cut    (tensile: adhesion only)
//
// g <= 0 is an exact test, not a floating-point gamble: both solvers project the gap,
// so contact points hold g = 0 exactly (polonsky_keer/PolonskyKeer.cpp sets it; the adhesive CG works
// in gap variables and clips them at 0, adhesive_cg/).
// The gap decides contact, not p > 0: with adhesion p < 0 in the cohesive zone of a
// closed contact, and p > 0 at open points is solver noise (below). For a hard wall the
// two agree: Polonsky–Keer sets g = 0 exactly where p > 0 (polonsky_keer/PolonskyKeer.cpp), and every
// validation and 512² challenge case had the same set under both rules when they were
// unified.
//
// stress_cut: 0 for a hard wall, where p is exactly 0 off contact. With adhesion the
// solver converges the pressure to a residual, not to zero where the interaction has
// vanished: stresses below kTensionNoise of the peak tension (w/ρ, or σ0 for Dugdale)
// are that noise, not contact. Measured when the rule was unified: |p| at open points
// where the law gives no compression was at most 2e-6 of the peak tension (Johnson,
// Maugis–Dugdale and the 512² challenge case), 500 times below the cut.
#pragma once

#include "cmc/contact/Interaction.hpp"
#include "cmc/grid/Grid.hpp"

#include <cstdint>
#include <vector>

namespace cmc {

using Mask = std::vector<std::uint8_t>;  // 1 = in contact, one entry per grid point

struct ContactRule {
  double contact_gap = 0.0;  // reduced length
  double stress_cut = 0.0;   // reduced pressure
  static constexpr double kTensionNoise = 1e-3;

  // The rule of a run: the interaction's noise cut and the case's contact gap.
  static ContactRule of(const Interaction& interaction, double contact_gap = 0.0) {
    return {contact_gap, kTensionNoise * peak_tension(interaction)};
  }
  bool in_contact(double gap) const { return gap <= contact_gap; }
  bool repulsive(double pressure) const { return pressure > stress_cut; }
  bool attractive(double pressure) const { return pressure < -stress_cut; }
};

// Points in contact (gap <= contact_gap), and as a fraction of the grid (0 for an empty field).
std::size_t contact_points(const Field& gap, const ContactRule& rule = {});
double contact_fraction(const Field& gap, const ContactRule& rule = {});
double repulsive_fraction(const Field& pressure, const ContactRule& rule = {});
double attractive_fraction(const Field& pressure, const ContactRule& rule = {});
Mask contact_mask(const Field& gap, const ContactRule& rule = {});
// Set points / all points of a mask (0 for an empty mask).
double mask_fraction(const Mask& mask);

}  // namespace cmc
