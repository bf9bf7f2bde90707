// What a scene needs, and what cmc leaves out of a run because the scene does not need it:
// adhesion's fields on a hard wall, observables that were not asked for, the zero padding
// of a free boundary on a periodic one. summary.json writes it as "model", beside the
// fields the solver holds (counted from its code) and the field bytes the run allocated
// (measured: grid/Grid.hpp field_bytes_peak), so that time and memory can be read against
// what was modelled.
#pragma once

#include "cmc/input/Case.hpp"

#include <string>
#include <vector>

namespace cmc {

struct SceneNeeds {
  std::string interaction;  // the case's word: "hard_wall", "exponential", "dugdale"
  bool adhesion = false;    // an interaction beyond the hard wall: the solver holds its fields
  std::string solver;       // the case's word
  bool observables = false;  // [observables] enabled: distributions, patches, spectrum per step
  bool fields_written = true;  // [output] fields: result.h5
  std::string boundary;     // "periodic" or "free" (free: the transforms run on 2nx x 2ny)
  std::string precision = "double";  // cmc computes in double precision only (no float path)
  SolverFields solver_fields;  // what the solver holds besides every run's fields
  // What the run leaves out because the scene does not need it, in words.
  std::vector<std::string> left_out;
};

SceneNeeds scene_needs(const Case& c);

}  // namespace cmc
