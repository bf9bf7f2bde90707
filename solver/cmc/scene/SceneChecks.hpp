// One numeric-validity check of the scene, in reduced units, before any solve.
//
// A case can hold values that are each finite and positive in SI and still make
// nonsense once converted: grid.size = 1e308 makes the force unit E* size² overflow (a
// load becomes 0), surface.radius = 1e-300 m makes a sphere's heights 1e295 grid sizes,
// surface.rms_gradient = 1e308 makes a surface of inf heights. Such a run used to end
// "converged" with Infinity, NaN or impossible numbers. The rule (cases/README.md,
// "Numbers"): the units (E* size², E* size³, E* size) must be finite normal doubles, and
// every number the solver reads, in reduced units (lengths over grid.size, pressures over
// E*), must be finite and, unless zero, of magnitude from kMinReduced to kMaxReduced, so
// that products of three of them stay finite. Anything else is bad input: CaseError
// (exit 2) naming the key and the value it became.
#pragma once

#include "cmc/input/Case.hpp"

#include <string>

namespace cmc {

struct Scene;

inline constexpr double kMaxReduced = 1e100, kMinReduced = 1e-100;

std::string short_number(double v);  // "%.6g", as the messages write numbers

// The units a case sets: its grid.size and contact modulus, and their products.
void check_unit_scales(const Case& c);

// Throws CaseError naming `key` when `reduced` (the value `si`, in `unit`, over `scale`
// of that unit) is not finite, or is not zero and outside [kMinReduced, kMaxReduced].
void require_reduced(const Case& c, const std::string& key, double si, const std::string& unit, double scale,
                     double reduced);

// The radius behind mu_T or lambda (the sphere's, or a rough surface's R_c on this grid,
// reduced), which must be finite and positive: a grid of 2 x 2 points resolves no curvature.
void require_curvature_radius(const Case& c, double radius);

// A Dugdale law's smoothing width (the case's, or the least that keeps grid points stable
// on this grid) must be below twice its range h0 (both in m).
void require_dugdale_smoothing(const Case& c, double smoothing, double twice_range);

// The heights (this rank's slab; collective in a distributed run) and the analytic
// shape's parameters; then every load step's target. given_heights: what the message calls heights
// handed in by the caller (null: the case's surface key).
void check_surface_numbers(const Case& c, const Scene& s, const char* given_heights = nullptr);
void check_load_numbers(const Case& c, const Scene& s);

}  // namespace cmc
