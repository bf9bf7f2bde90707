// Every `kind`-like choice of a case file as a typed value, with the one table that
// maps it to the word written in case files. The case parser turns the words into
// these values (input/Case.cpp); nothing downstream compares strings. The words come
// back only where a name is printed (messages, summary.json).
#pragma once

#include <array>
#include <string_view>

namespace cmc {

enum class SurfaceKind { Sphere, Wavy1d, Wavy2d, Flat, SelfAffine, File };
enum class SurfaceFormat { ChallengeHdf5, ChallengeAscii, Fourier, Hdf5, Ascii };
enum class InteractionKind { HardWall, Exponential, Dugdale };
// How an exponential law is put on a grid whose spacing does not resolve its range:
// None samples it at the grid points; Range lengthens the range to the shortest that
// leaves no grid point bistable, keeping w (contact/Interaction.hpp, coarse_grained_range);
// Shape keeps w and the peak tension and gives the law the least curvature that leaves no
// grid point bistable (shape_coarse_grained).
enum class CoarseGraining { None, Range, Shape };
// Auto: Polonsky-Keer for a hard wall; with exponential adhesion on a loading path
// (increasing load, no unloading) the quasi-static loading-branch solver; the adhesive CG
// otherwise. The parser resolves it, so a parsed Case never holds Auto.
enum class SolverKind { Auto, PolonskyKeer, AdhesiveCg, QuasiStatic };
enum class LoadControl { Force, MeanPressure, Penetration, MeanGap };
enum class ValidationReference { Hertz, HertzPeriodic, Westergaard, Jkr, MaugisDugdale, Johnson };
enum class ValidationQuantity { Penetration, PressureProfile, MeanPressure, MeanGap, Force, Pulloff };
// The stability checks of a [[validation.check]] with `kind` (validation/Stability.hpp says
// what each measures): they need no analytic reference.
enum class StabilityKind {
  Iterations, ResidualGrowth, EnergyRise, SameBits, Threads, Continuity, Agreement,
  ForceBalance, Gap, ContactFraction, Pulloff, Hysteresis
};
// What a continuity check compares between a case and the case with one parameter changed.
enum class PathObservable { ContactFraction, MeanGap, MeanPressure, Penetration, Pulloff };

template <class E>
struct KindName {
  E value;
  std::string_view name;
};

// The words of each choice, in the order cases/README.md lists them.
constexpr std::array<KindName<SurfaceKind>, 6> kind_names(SurfaceKind) {
  using enum SurfaceKind;
  return {{{Sphere, "sphere"}, {Wavy1d, "wavy1d"}, {Wavy2d, "wavy2d"}, {Flat, "flat"}, {SelfAffine, "self_affine"},
           {File, "file"}}};
}
constexpr std::array<KindName<SurfaceFormat>, 5> kind_names(SurfaceFormat) {
  using enum SurfaceFormat;
  return {{{ChallengeHdf5, "challenge_hdf5"}, {ChallengeAscii, "challenge_ascii"}, {Fourier, "fourier"},
           {Hdf5, "hdf5"}, {Ascii, "ascii"}}};
}
constexpr std::array<KindName<InteractionKind>, 3> kind_names(InteractionKind) {
  using enum InteractionKind;
  return {{{HardWall, "hard_wall"}, {Exponential, "exponential"}, {Dugdale, "dugdale"}}};
}
constexpr std::array<KindName<CoarseGraining>, 3> kind_names(CoarseGraining) {
  using enum CoarseGraining;
  return {{{None, "none"}, {Range, "range"}, {Shape, "shape"}}};
}
constexpr std::array<KindName<SolverKind>, 4> kind_names(SolverKind) {
  using enum SolverKind;
  return {{{Auto, "auto"}, {PolonskyKeer, "polonsky_keer"}, {AdhesiveCg, "adhesive_cg"}, {QuasiStatic, "quasi_static"}}};
}
constexpr std::array<KindName<LoadControl>, 4> kind_names(LoadControl) {
  using enum LoadControl;
  return {{{Force, "force"}, {MeanPressure, "mean_pressure"}, {Penetration, "penetration"}, {MeanGap, "mean_gap"}}};
}
constexpr std::array<KindName<ValidationReference>, 6> kind_names(ValidationReference) {
  using enum ValidationReference;
  return {{{Hertz, "hertz"}, {HertzPeriodic, "hertz_periodic"}, {Westergaard, "westergaard"}, {Jkr, "jkr"},
           {MaugisDugdale, "maugis_dugdale"}, {Johnson, "johnson"}}};
}
constexpr std::array<KindName<ValidationQuantity>, 6> kind_names(ValidationQuantity) {
  using enum ValidationQuantity;
  return {{{Penetration, "penetration"}, {PressureProfile, "pressure_profile"}, {MeanPressure, "mean_pressure"},
           {MeanGap, "mean_gap"}, {Force, "force"}, {Pulloff, "pulloff"}}};
}

constexpr std::array<KindName<StabilityKind>, 12> kind_names(StabilityKind) {
  using enum StabilityKind;
  return {{{Iterations, "iterations"}, {ResidualGrowth, "residual_growth"}, {EnergyRise, "energy_rise"},
           {SameBits, "same_bits"}, {Threads, "threads"}, {Continuity, "continuity"}, {Agreement, "agreement"},
           {ForceBalance, "force_balance"},
           {Gap, "gap"}, {ContactFraction, "contact_fraction"}, {Pulloff, "pulloff"}, {Hysteresis, "hysteresis"}}};
}
constexpr std::array<KindName<PathObservable>, 5> kind_names(PathObservable) {
  using enum PathObservable;
  return {{{ContactFraction, "contact_fraction"}, {MeanGap, "mean_gap"}, {MeanPressure, "mean_pressure"},
           {Penetration, "penetration"}, {Pulloff, "pulloff"}}};
}

// The case-file word of a value.
template <class E>
constexpr std::string_view kind_name(E value) {
  for (const auto& k : kind_names(value))
    if (k.value == value) return k.name;
  return "?";
}

}  // namespace cmc
