// Surfaces from Python: the challenge's self-affine generator and the height-file readers
// (surface/SelfAffine.hpp, surface/SurfaceIO.hpp), heights in metres as numpy arrays over
// the library's own buffers.
#include "arrays.hpp"
#include "bindings.hpp"

#include "cmc/input/Case.hpp"
#include "cmc/input/Kinds.hpp"
#include "cmc/scene/Scene.hpp"
#include "cmc/surface/SelfAffine.hpp"
#include "cmc/surface/SurfaceIO.hpp"

#include <string>

namespace cmcpy {

namespace {

// The heights of `map` times `to_m` (metres per height unit), in place, as a (ny, nx) array.
py::array_t<double> heights_in_metres(cmc::HeightMap&& map, double to_m) {
  scale_in_place(map.heights, to_m);
  return adopt_field(std::move(map.heights), map.grid.nx, map.grid.ny);
}

// The self-affine surface of a checked case ([surface] kind = "self_affine", a square
// grid): the heights in metres, and how many of the band's modes the grid holds.
py::dict self_affine(const cmc::Case& c) {
  cmc::Units u;
  u.length_m = c.grid.size_x;
  const cmc::SelfAffineSpec spec = cmc::self_affine_spec(c.surface, u);
  cmc::SelfAffineSurface s;
  int full_grid = 0;
  {
    py::gil_scoped_release free;
    s = cmc::generate_self_affine(spec, c.grid.nx);
    if (s.low_passed()) full_grid = cmc::self_affine_modes(spec).full_grid();
  }
  py::dict d;
  d["modes_total"] = s.modes_total;
  d["modes_dropped"] = s.modes_dropped;
  d["full_grid"] = full_grid;
  d["heights"] = heights_in_metres(std::move(s.map), u.length_m);
  return d;
}

cmc::SurfaceFormat format_named(const std::string& name) {
  std::string known;
  for (const auto& k : cmc::kind_names(cmc::SurfaceFormat{})) {
    if (k.name == name) return k.value;
    known += std::string(known.empty() ? "" : ", ") + "\"" + std::string(k.name) + "\"";
  }
  throw cmc::CaseError("format: expected one of " + known + ", got \"" + name + "\"");
}

// A height file in one of the formats a case's [surface] reads (kind = "file"), on its own
// grid (no interpolation). `size`: the side of the box in metres; `height_unit`: metres per
// height unit of the file, 0 for the format's own (`size` for the challenge's formats and
// Fourier lists, whose heights are in units of L; else 1). `n`: a Fourier list's grid (0:
// the smallest that holds every mode).
py::array_t<double> read_heights(const std::string& path, const std::string& format, double size,
                                 const std::string& dataset, double height_unit, int n) {
  const cmc::SurfaceFormat f = format_named(format);
  using enum cmc::SurfaceFormat;
  const bool in_units_of_l = f == ChallengeHdf5 || f == ChallengeAscii || f == Fourier;
  const double to_m = height_unit > 0.0 ? height_unit : in_units_of_l ? size : 1.0;
  cmc::HeightMap map;
  {
    py::gil_scoped_release free;
    switch (f) {
      case ChallengeHdf5: map = cmc::read_challenge_hdf5(path); break;
      case ChallengeAscii: map = cmc::read_challenge_ascii(path); break;
      case Fourier: map = cmc::read_fourier_heights(path, n); break;
      case Hdf5: map = cmc::read_hdf5_heights(path, dataset, size, size); break;
      case Ascii: map = cmc::read_ascii_heights(path, size, size); break;
    }
  }
  return heights_in_metres(std::move(map), to_m);
}

}  // namespace

void bind_surface(py::module_& m) {
  m.def("self_affine", &self_affine, py::arg("case"),
        "The self-affine surface of a checked case: {'heights': metres, 'modes_total', 'modes_dropped', "
        "'full_grid'}.");
  m.def("read_heights", &read_heights, py::arg("path"), py::arg("format"), py::arg("size"), py::arg("dataset"),
        py::arg("height_unit"), py::arg("n"), "Heights in metres from a height file (the formats of a case file).");
}

}  // namespace cmcpy
