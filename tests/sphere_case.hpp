// The tests' smallest case file: a rigid sphere (R = 1 cm) on a 1 mm cell of an elastic
// half-space (E* = 1 MPa), loaded at the given values. The name, grid, boundary, control and
// loads vary between tests; more tables go after the text it returns.
#pragma once

#include <string>

inline std::string sphere_case_text(const std::string& name, int n, const std::string& values,
                                    const std::string& control = "force", const std::string& boundary = "") {
  std::string t = "[case]\nname = \"" + name + "\"\n";
  t += "[grid]\nn = " + std::to_string(n) + "\nsize = 1e-3\n";
  if (!boundary.empty()) t += "boundary = \"" + boundary + "\"\n";
  t += "[material]\ncontact_modulus = 1e6\n";
  t += "[surface]\nkind = \"sphere\"\nradius = 1e-2\n";
  t += "[loading]\ncontrol = \"" + control + "\"\nvalues = [" + values + "]\n";
  return t;
}
