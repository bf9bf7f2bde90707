#include "cmc/output/Hdf5Fields.hpp"

#include "cmc/grid/Ranks.hpp"
#include "cmc/surface/H5Handle.hpp"

#include <algorithm>
#include <stdexcept>

namespace cmc::h5 {

void check(long long status, const std::string& what) {
  if (status < 0) throw std::runtime_error("HDF5: " + what + " failed");
}
void attr_string(hid_t obj, const char* name, const std::string& value) {
  H5Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, value.size() + 1);
  H5Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  H5Handle a(H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  check(a, std::string("attribute ") + name);
  check(H5Awrite(a, type, value.c_str()), std::string("attribute ") + name);
}
void attr_double(hid_t obj, const char* name, double value) {
  H5Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  H5Handle a(H5Acreate2(obj, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  check(a, std::string("attribute ") + name);
  check(H5Awrite(a, H5T_NATIVE_DOUBLE, &value), std::string("attribute ") + name);
}
void dataset(hid_t where, const std::string& name, const Grid& g, const Field& values, double scale, const char* unit,
             const char* meaning) {
  const hsize_t nx = hsize_t(g.nx);
  H5Handle space, d;
  if (is_root()) {
    hsize_t dims[2] = {hsize_t(g.ny), nx};
    space = H5Handle(H5Screate_simple(2, dims, nullptr), H5Sclose);
    d = H5Handle(H5Dcreate2(where, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                 H5Dclose);
    check(d, "dataset " + name);
  }
  // Scaled and written a block of rows at a time (about 2^20 values, 8 MB): a field is
  // never held twice on the host while it is written (a 32768² field is 8.6 GB).
  const std::size_t block_rows = std::max<std::size_t>(1, (std::size_t(1) << 20) / std::size_t(nx));
  Field scaled;
  for_each_slab(g, values.data(), [&](int y0, int rows, const double* v) {
    for (std::size_t r0 = 0; r0 < std::size_t(rows); r0 += block_rows) {
      const std::size_t rr = std::min(block_rows, std::size_t(rows) - r0), n = rr * nx;
      scaled.resize(n);
      const double* src = v + r0 * nx;
      for (std::size_t i = 0; i < n; ++i) scaled[i] = src[i] * scale;
      hsize_t start[2] = {hsize_t(y0) + hsize_t(r0), 0}, count[2] = {hsize_t(rr), nx};
      H5Handle mem(H5Screate_simple(2, count, nullptr), H5Sclose);
      check(H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr), "selecting rows of " + name);
      check(H5Dwrite(d, H5T_NATIVE_DOUBLE, mem, space, H5P_DEFAULT, scaled.data()), "writing " + name);
    }
  });
  if (!is_root()) return;
  attr_string(d, "units", unit);
  attr_string(d, "description", meaning);
}
void vector_dataset(hid_t where, const std::string& name, const std::vector<double>& v, const char* unit) {
  hsize_t dims[1] = {hsize_t(v.size())};
  H5Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose);
  H5Handle d(H5Dcreate2(where, name.c_str(), H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
             H5Dclose);
  check(d, "dataset " + name);
  if (!v.empty()) check(H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "writing " + name);
  attr_string(d, "units", unit);
}
void text_dataset(hid_t where, const char* name, const std::string& text) {
  H5Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, text.size() + 1);
  H5Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  H5Handle d(H5Dcreate2(where, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  check(d, std::string("dataset ") + name);
  check(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, text.c_str()), std::string("writing ") + name);
}
bool read_text(hid_t where, const char* name, std::string& text) {
  H5Handle d(H5Dopen2(where, name, H5P_DEFAULT), H5Dclose);
  if (!d.ok()) return false;
  H5Handle type(H5Dget_type(d), H5Tclose);
  if (!type.ok() || H5Tget_class(type) != H5T_STRING) return false;
  const std::size_t n = H5Tget_size(type);
  std::string buf(n, '\0');
  if (n == 0 || H5Dread(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()) < 0) return false;
  text = buf.substr(0, buf.find('\0'));
  return true;
}
void write_fields(hid_t where, const char* group, const Grid& g, const std::vector<NamedField<const Field>>& fields) {
  H5Handle grp;
  if (is_root()) {
    grp = H5Handle(H5Gcreate2(where, group, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
    check(grp, std::string("group ") + group);
  }
  for (const auto& f : fields) dataset(grp, f.name, g, *f.field, 1.0, f.unit, "reduced value (checkpoint)");
}
bool read_fields(hid_t where, const char* group, const Grid& g, const std::vector<NamedField<Field>>& fields) {
  const std::size_t k = fields.size();
  H5Handle grp;
  std::vector<H5Handle> d(k), space(k);
  bool ok = true;
  if (is_root()) {
    grp = H5Handle(H5Gopen2(where, group, H5P_DEFAULT), H5Gclose);
    ok = grp.ok();
    for (std::size_t i = 0; ok && i < k; ++i) {
      d[i] = H5Handle(H5Dopen2(grp, fields[i].name, H5P_DEFAULT), H5Dclose);
      if (d[i].ok()) space[i] = H5Handle(H5Dget_space(d[i]), H5Sclose);
      hsize_t dims[2] = {0, 0};
      ok = d[i].ok() && space[i].ok() && H5Sget_simple_extent_ndims(space[i]) == 2 &&
           H5Sget_simple_extent_dims(space[i], dims, nullptr) == 2 && dims[0] == hsize_t(g.ny) && dims[1] == hsize_t(g.nx);
    }
  }
  if (!any_rank(ok)) return false;
  bool read_ok = true;
  for (std::size_t i = 0; i < k; ++i) {
    fields[i].field->resize(g.size());
    scatter_slabs(g, fields[i].field->data(), [&](int y0, int rows, double* v) {
      hsize_t start[2] = {hsize_t(y0), 0}, count[2] = {hsize_t(rows), hsize_t(g.nx)};
      H5Handle mem(H5Screate_simple(2, count, nullptr), H5Sclose);
      read_ok = read_ok && H5Sselect_hyperslab(space[i], H5S_SELECT_SET, start, nullptr, count, nullptr) >= 0;
      read_ok = read_ok && H5Dread(d[i], H5T_NATIVE_DOUBLE, mem, space[i], H5P_DEFAULT, v) >= 0;
    });
  }
  return !any_rank(!read_ok);
}

}  // namespace cmc::h5
