// Case-file rules decided for inputs that used to pass or fail unclearly (cases/README.md):
// a solver tolerance too loose to mean anything, an integer key written as a float, a key
// of another surface or interaction kind, and spaces in a --set.
#include "cmc/input/Case.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

using namespace cmc;

namespace {
// The sphere of cases/validation/hertz-free.toml (a hard wall).
const std::string kSphere = std::string(CMC_SOURCE_DIR) + "/cases/validation/hertz-free.toml";
// The CaseError message of reading it with `overrides` ("" if none).
std::string error_of(const std::vector<std::string>& overrides) {
  try {
    load_case(kSphere, overrides);
  } catch (const CaseError& e) {
    return e.what();
  }
  return "";
}
#define EXPECT_HAS(text, fragment) EXPECT_NE(std::string(text).find(fragment), std::string::npos) << (text)
}  // namespace

// A relative residual above 1e-2 stopped solves after 0 or 1 iterations ("converged").
TEST(DecidedInputs, SolverToleranceAtMostOnePercent) {
  EXPECT_EQ(error_of({"solver.tolerance=1e-2"}), "");
  for (const char* t : {"solver.tolerance=10", "solver.tolerance=1", "solver.tolerance=0.5"})
    EXPECT_HAS(error_of({t}), "[solver] tolerance: expected a relative residual of at most 0.01");
}

TEST(DecidedInputs, AnIntegerWrittenAsAFloatSaysSo) {
  EXPECT_HAS(error_of({"grid.n=64.0"}), "[grid] n: expected a positive number of points per side (a whole number, "
                                        "written without a decimal point), got a number 64.0");
}

TEST(DecidedInputs, AKeyOfAnotherKindNamesItsKind) {
  EXPECT_HAS(error_of({"surface.amplitude=1e-6"}),
             "[surface] amplitude: applies only with kind = \"wavy1d\" or \"wavy2d\" (this case's kind is \"sphere\")");
  EXPECT_HAS(error_of({"interaction.range=1e-6"}),
             "[interaction] range: applies only with kind = \"exponential\" or \"dugdale\" (this case's kind is "
             "\"hard_wall\")");
  EXPECT_HAS(error_of({"surface.radiu=1"}), "[surface] radiu: unknown key");
}

TEST(DecidedInputs, SpacesAroundTheKeyOfASetAreAllowed) {
  EXPECT_EQ(load_case(kSphere, {" grid.n = 64"}).grid.nx, 64);
  EXPECT_HAS(error_of({" = 64"}), "expected section.key=value");
}
