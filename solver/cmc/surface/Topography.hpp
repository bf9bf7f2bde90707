// The rigid indenter's surface: heights h(x, y) on the grid, in reduced units.
//
// The indenter is pressed down onto the elastic half-space; its lowest points touch
// first. With rigid-body approach δ and surface displacement u (into the solid),
// the gap is g = h − δ + u ≥ 0 (see HalfSpace.hpp for signs).
// Simple analytic shapes live here; the challenge's self-affine surface and the
// height-file readers have their own headers (SelfAffine.hpp, SurfaceIO.hpp).
#pragma once

#include "cmc/grid/Grid.hpp"

#include <string>

namespace cmc {

struct Topography {
  Grid grid;
  Field heights;
  std::string description;  // where the heights came from, for summaries
};

// Paraboloid h = r²/(2R) with its apex at (x0, y0): the Hertz sphere in the
// small-slope approximation. Periodic grids use the minimum-image distance.
Topography sphere(const Grid& g, double radius, double x0, double y0, bool periodic);
// One-dimensional wavy surface h = a (1 − cos(2π x / λ)) = 2a sin²(π x/λ): the
// Westergaard / Johnson (1995) profile; uniform along y.
Topography wavy1d(const Grid& g, double amplitude, double wavelength);
// Two-dimensional wavy surface h = a (1 − cos(2πx/λ) cos(2πy/λ)) (Johnson,
// Greenwood & Higginson 1985), lowest point at the origin.
Topography wavy2d(const Grid& g, double amplitude, double wavelength);
Topography flat(const Grid& g);

}  // namespace cmc
