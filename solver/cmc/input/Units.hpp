// The one place where SI meets cmc's reduced units.
//
// Inside cmc, lengths are in units of the system size (the case's grid.size, in m)
// and pressures in units of the contact modulus E* (Pa); for the challenge this is
// exactly the problem definition's unit system (L = 1, E* ḡ = 1 with ḡ = 1).
// Forces are then in units of E* L², energies per area (work of adhesion) in E* L.
// Case files and outputs speak SI; nothing else converts.
#pragma once

namespace cmc {

struct Units {
  double length_m = 1.0;     // one reduced length unit, in metres
  double pressure_pa = 1.0;  // one reduced pressure unit, in pascals

  double length(double metres) const { return metres / length_m; }
  double pressure(double pascals) const { return pascals / pressure_pa; }
  double force(double newtons) const { return newtons / (pressure_pa * length_m * length_m); }
  double energy_per_area(double j_per_m2) const { return j_per_m2 / (pressure_pa * length_m); }

  double to_m(double l) const { return l * length_m; }
  double to_pa(double p) const { return p * pressure_pa; }
  double to_n(double f) const { return f * pressure_pa * length_m * length_m; }
  double to_j_per_m2(double w) const { return w * pressure_pa * length_m; }
  double to_j(double e) const { return e * pressure_pa * length_m * length_m * length_m; }
};

}  // namespace cmc
