// RAII for HDF5 (here, upstream of output/, so that both the surface reader and the
// result writer can use it): every identifier cmc opens (file, group, dataset, dataspace, datatype,
// attribute, property list) lives in an H5Handle, which closes it when the handle goes out
// of scope, so an exception thrown between open and close cannot leak it. Used by the
// result writer (output/Hdf5Fields.cpp and the files using it) and the surface reader/writer
// (surface/SurfaceIO.cpp).
#pragma once

#include <hdf5.h>

#include <utility>

namespace cmc {

class H5Handle {
 public:
  using Close = herr_t (*)(hid_t);
  H5Handle() = default;
  // Takes ownership of `id` (a negative id, i.e. a failed open, owns nothing).
  H5Handle(hid_t id, Close close) : id_(id), close_(close) {}
  H5Handle(const H5Handle&) = delete;
  H5Handle& operator=(const H5Handle&) = delete;
  H5Handle(H5Handle&& o) noexcept : id_(std::exchange(o.id_, -1)), close_(o.close_) {}
  H5Handle& operator=(H5Handle&& o) noexcept {
    if (this != &o) reset(), id_ = std::exchange(o.id_, -1), close_ = o.close_;
    return *this;
  }
  ~H5Handle() { reset(); }

  // Closes now; returns the close call's status (negative: failed, e.g. a file whose
  // last write could not be flushed), 0 when nothing was open.
  herr_t reset() {
    herr_t r = 0;
    if (id_ >= 0 && close_) r = close_(id_);
    id_ = -1;
    return r;
  }
  // Gives up ownership (the caller closes the id).
  hid_t release() { return std::exchange(id_, -1); }
  bool ok() const { return id_ >= 0; }
  operator hid_t() const { return id_; }

 private:
  hid_t id_ = -1;
  Close close_ = nullptr;
};

// Silences HDF5's automatic error-stack printing for a scope (only cmc's own messages
// show), and restores the previous handler on exit.
class H5Quiet {
 public:
  H5Quiet() {
    H5Eget_auto2(H5E_DEFAULT, &func_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  H5Quiet(const H5Quiet&) = delete;
  H5Quiet& operator=(const H5Quiet&) = delete;
  ~H5Quiet() { H5Eset_auto2(H5E_DEFAULT, func_, data_); }

 private:
  H5E_auto2_t func_ = nullptr;
  void* data_ = nullptr;
};

}  // namespace cmc
