// The quasi-static solver's test patch (tests/test_quasi_static.cpp, and the device code's
// tests in tests/emulation): a rough periodic 128² patch whose grid spacing is 24 ρ, as the
// challenge at 2048² (every point bistable, w/ρ = E*).
#pragma once

#include "cmc/surface/SelfAffine.hpp"

struct RoughPatch {
  static constexpr int n = 128;
  cmc::HeightMap map;
  double rho, w, load;
  RoughPatch() {
    cmc::SelfAffineSpec spec;
    spec.hurst = 0.8;
    spec.rolloff_wavelength = 0.2;
    spec.cutoff_wavelength = 2.0 / n;  // as the challenge at 2048²: λ_s ≈ 2 Δx
    spec.rms_gradient = 1.0;
    spec.seed = 11;
    map = cmc::generate_self_affine(spec, n).map;
    rho = map.grid.dx() / 24.0;  // Δx = 24 ρ, as the challenge at 2048²
    w = rho;                     // peak tension w/ρ = E* (the challenge: 0.97 E*)
    load = 0.01;                 // p/(E* ḡ), the challenge's reference load
  }
};
