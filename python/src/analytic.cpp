// cmc._core.analytic: the analytic references of solver/cmc/analytic/Analytic.hpp, the
// functions the validation checks use. Functions of numbers that return a number take
// numpy arrays too (numpy broadcasting). Any consistent units; the conventions, equations
// and citations are in Analytic.hpp.
#include "bindings.hpp"

#include "cmc/analytic/Analytic.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <sstream>

namespace cmcpy {

namespace py = pybind11;
namespace an = cmc::analytic;

namespace {

// A result struct as a read-only Python class with a readable repr.
template <class T, class... Fields>
void bind_record(py::module_& m, const char* name, const char* doc, Fields... fields) {
  py::class_<T> c(m, name, doc);
  std::vector<std::string> names;
  (
      [&] {
        c.def_readonly(fields.first, fields.second);
        names.push_back(fields.first);
      }(),
      ...);
  c.def("__repr__", [name, names](const py::object& self) {
    std::ostringstream s;
    s << name << "(";
    for (std::size_t i = 0; i < names.size(); ++i)
      s << (i ? ", " : "") << names[i] << "=" << std::string(py::repr(self.attr(names[i].c_str())));
    s << ")";
    return s.str();
  });
}

template <class T>
std::pair<const char*, double T::*> field(const char* name, double T::*member) {
  return {name, member};
}

void bind_records(py::module_& m) {
  using an::HertzContact, an::AdhesiveContact, an::SinusoidPoint, an::MDScales, an::MDPoint, an::MDContact;
  bind_record<HertzContact>(m, "HertzContact", "Hertz contact: radius a, penetration delta, force F, max_pressure p0.",
                            field("radius", &HertzContact::radius), field("penetration", &HertzContact::penetration),
                            field("force", &HertzContact::force), field("max_pressure", &HertzContact::max_pressure));
  bind_record<AdhesiveContact>(m, "AdhesiveContact", "JKR/DMT contact: radius a, penetration delta, force F.",
                               field("radius", &AdhesiveContact::radius),
                               field("penetration", &AdhesiveContact::penetration),
                               field("force", &AdhesiveContact::force));
  bind_record<SinusoidPoint>(m, "SinusoidPoint", "Johnson's adhesive sinusoid: half_width a, mean_pressure pbar.",
                             field("half_width", &SinusoidPoint::half_width),
                             field("mean_pressure", &SinusoidPoint::mean_pressure));
  bind_record<MDScales>(m, "MDScales", "Maugis' units of A, Pbar and Delta.", field("radius", &MDScales::radius),
                        field("force", &MDScales::force), field("penetration", &MDScales::penetration));
  bind_record<MDPoint>(m, "MDPoint", "A point of the Maugis-Dugdale curve in Maugis' reduced units.",
                       field("A", &MDPoint::A), field("m", &MDPoint::m), field("Pbar", &MDPoint::Pbar),
                       field("Delta", &MDPoint::Delta));
  bind_record<MDContact>(m, "MDContact", "Maugis-Dugdale contact: radius a, zone_radius c, force F, penetration delta.",
                         field("radius", &MDContact::radius), field("zone_radius", &MDContact::zone_radius),
                         field("force", &MDContact::force), field("penetration", &MDContact::penetration));
}

void bind_hertz(py::module_& m) {
  m.def("hertz_from_force", &an::hertz_from_force, py::arg("Estar"), py::arg("R"), py::arg("F"));
  m.def("hertz_from_penetration", &an::hertz_from_penetration, py::arg("Estar"), py::arg("R"), py::arg("delta"));
  m.def("hertz_from_radius", &an::hertz_from_radius, py::arg("Estar"), py::arg("R"), py::arg("a"));
  m.def("hertz_pressure", py::vectorize(an::hertz_pressure), py::arg("Estar"), py::arg("R"), py::arg("a"), py::arg("r"),
        "p(r) = p0 sqrt(1 - r^2/a^2) for r < a, 0 outside.");
  m.def("hertz_stiffness", py::vectorize(an::hertz_stiffness), py::arg("Estar"), py::arg("a"));
  m.def("hertz_gap", py::vectorize(an::hertz_gap), py::arg("R"), py::arg("a"), py::arg("r"),
        "Gap between the sphere and the deformed half-space at radius r (0 for r <= a).");
  m.def("periodic_sphere_shift_coefficient", &an::periodic_sphere_shift_coefficient);
  m.def("hertz_periodic_penetration", py::vectorize(an::hertz_periodic_penetration), py::arg("Estar"), py::arg("R"),
        py::arg("F"), py::arg("L"), "delta_Hertz(F) - c F/(Estar L): a sphere in a periodic square cell of side L.");
  m.def("flat_punch_pressure", py::vectorize(an::flat_punch_pressure), py::arg("F"), py::arg("a"), py::arg("r"));
  m.def("flat_punch_penetration", py::vectorize(an::flat_punch_penetration), py::arg("Estar"), py::arg("a"),
        py::arg("F"));
  m.def("periodic_strip_punch_pressure", py::vectorize(an::periodic_strip_punch_pressure), py::arg("pbar"),
        py::arg("wavelength"), py::arg("a"), py::arg("x"));
}

void bind_wavy(py::module_& m) {
  m.def("westergaard_full_contact_pressure", py::vectorize(an::westergaard_full_contact_pressure), py::arg("Estar"),
        py::arg("h"), py::arg("wavelength"), "p* of the profile h (1 - cos(2 pi x/wavelength)).");
  m.def("westergaard_mean_pressure", py::vectorize(an::westergaard_mean_pressure), py::arg("Estar"), py::arg("h"),
        py::arg("wavelength"), py::arg("a"));
  m.def("westergaard_half_width", py::vectorize(an::westergaard_half_width), py::arg("Estar"), py::arg("h"),
        py::arg("wavelength"), py::arg("pbar"));
  m.def("westergaard_pressure", py::vectorize(an::westergaard_pressure), py::arg("Estar"), py::arg("h"),
        py::arg("wavelength"), py::arg("a"), py::arg("x"));
  m.def("westergaard_mean_gap", py::vectorize(an::westergaard_mean_gap), py::arg("Estar"), py::arg("h"),
        py::arg("wavelength"), py::arg("pbar"));
  m.def("sinusoid_pressure", py::vectorize(an::sinusoid_pressure), py::arg("Estar"), py::arg("h"),
        py::arg("wavelength"), py::arg("a"), py::arg("pbar"), py::arg("x"));
  m.def("sinusoid_mean_gap", py::vectorize(an::sinusoid_mean_gap), py::arg("Estar"), py::arg("h"),
        py::arg("wavelength"), py::arg("a"), py::arg("pbar"));
  m.def("johnson_alpha", py::vectorize(an::johnson_alpha), py::arg("Estar"), py::arg("w"), py::arg("h"),
        py::arg("wavelength"));
  m.def("johnson_mean_pressure", py::vectorize(an::johnson_mean_pressure), py::arg("Estar"), py::arg("w"),
        py::arg("h"), py::arg("wavelength"), py::arg("a"));
  m.def("johnson_pressure", py::vectorize(an::johnson_pressure), py::arg("Estar"), py::arg("w"), py::arg("h"),
        py::arg("wavelength"), py::arg("a"), py::arg("x"));
  m.def("johnson_mean_gap", py::vectorize(an::johnson_mean_gap), py::arg("Estar"), py::arg("w"), py::arg("h"),
        py::arg("wavelength"), py::arg("a"));
  m.def("johnson_half_width", py::vectorize(an::johnson_half_width), py::arg("Estar"), py::arg("w"), py::arg("h"),
        py::arg("wavelength"), py::arg("pbar"));
  m.def("johnson_pulloff", &an::johnson_pulloff, py::arg("Estar"), py::arg("w"), py::arg("h"), py::arg("wavelength"));
  m.def("johnson_full_contact_alpha", &an::johnson_full_contact_alpha);
}

void bind_adhesive_spheres(py::module_& m) {
  m.def("jkr_force", py::vectorize(an::jkr_force), py::arg("Estar"), py::arg("R"), py::arg("w"), py::arg("a"));
  m.def("jkr_penetration", py::vectorize(an::jkr_penetration), py::arg("Estar"), py::arg("R"), py::arg("w"),
        py::arg("a"));
  m.def("jkr_radius_from_force", py::vectorize(an::jkr_radius_from_force), py::arg("Estar"), py::arg("R"),
        py::arg("w"), py::arg("F"));
  m.def("jkr_zero_load_radius", py::vectorize(an::jkr_zero_load_radius), py::arg("Estar"), py::arg("R"), py::arg("w"));
  m.def("jkr_pulloff_load_controlled", &an::jkr_pulloff_load_controlled, py::arg("Estar"), py::arg("R"), py::arg("w"));
  m.def("jkr_pulloff_displacement_controlled", &an::jkr_pulloff_displacement_controlled, py::arg("Estar"),
        py::arg("R"), py::arg("w"));
  m.def("dmt_force", py::vectorize(an::dmt_force), py::arg("Estar"), py::arg("R"), py::arg("w"), py::arg("a"));
  m.def("dmt_penetration", py::vectorize(an::dmt_penetration), py::arg("R"), py::arg("a"));
  m.def("dmt_radius_from_force", py::vectorize(an::dmt_radius_from_force), py::arg("Estar"), py::arg("R"),
        py::arg("w"), py::arg("F"));
  m.def("md_scales", &an::md_scales, py::arg("Estar"), py::arg("R"), py::arg("w"));
  m.def("md_lambda", py::vectorize(an::md_lambda), py::arg("Estar"), py::arg("R"), py::arg("w"), py::arg("sigma0"));
  m.def("md_lambda_from_tabor", py::vectorize(an::md_lambda_from_tabor), py::arg("mu_T"));
  m.def("md_point", &an::md_point, py::arg("lam"), py::arg("A"));
  m.def("md_zero_radius_limit", &an::md_zero_radius_limit, py::arg("lam"));
  m.def("md_pulloff", &an::md_pulloff, py::arg("lam"));
  m.def("md_curve", &an::md_curve, py::arg("lam"), py::arg("A_min"), py::arg("A_max"), py::arg("n"));
  m.def("md_contact", &an::md_contact, py::arg("Estar"), py::arg("R"), py::arg("w"), py::arg("sigma0"), py::arg("a"));
}

}  // namespace

void bind_analytic(py::module_& m) {
  m.doc() = "The analytic references of cmc (solver/cmc/analytic/Analytic.hpp): Hertz, flat punches, periodic "
            "images, Westergaard and Johnson's wavy contacts, JKR, DMT and Maugis-Dugdale. Compressive p > 0, "
            "penetration delta > 0 into the solid; any consistent units.";
  bind_records(m);
  bind_hertz(m);
  bind_wavy(m);
  bind_adhesive_spheres(m);
}

}  // namespace cmcpy
