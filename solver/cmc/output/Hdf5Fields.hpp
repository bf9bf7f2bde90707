// The HDF5 pieces of a run's files (result.h5, the steps' files and the checkpoint):
// attributes, (ny, nx) datasets of fields written and read a slab per rank, vectors and
// texts. Every identifier is held by an H5Handle (surface/H5Handle.hpp): a check() that
// throws closes whatever was opened before it. Internal to the output layer.
#pragma once

#include "cmc/grid/Grid.hpp"

#include <hdf5.h>

#include <string>
#include <vector>

namespace cmc::h5 {

// Throws "HDF5: <what> failed" when status is negative.
void check(long long status, const std::string& what);
void attr_string(hid_t obj, const char* name, const std::string& value);
void attr_double(hid_t obj, const char* name, double value);
// A (ny, nx) dataset of `values` times `scale`, with its unit. In a distributed run
// every rank calls it with its slab: rank 0 writes the rows of each rank in turn
// (holding one slab at a time; `where` is used on rank 0 only), the others send theirs.
void dataset(hid_t where, const std::string& name, const Grid& g, const Field& values, double scale, const char* unit,
             const char* meaning);
void vector_dataset(hid_t where, const std::string& name, const std::vector<double>& v, const char* unit);
// A text as a scalar string dataset (no size limit, unlike an attribute).
void text_dataset(hid_t where, const char* name, const std::string& text);
bool read_text(hid_t where, const char* name, std::string& text);

// Reduced fields of a checkpoint, exactly as the solver holds them: (name, field, unit).
// F is Field for reading into, const Field for writing from; one list of names serves both.
template <class F>
struct NamedField {
  const char* name;
  F* field;
  const char* unit;
};
// The (ny, nx) datasets of `group`, one per field.
void write_fields(hid_t where, const char* group, const Grid& g, const std::vector<NamedField<const Field>>& fields);
// The (ny, nx) datasets of `group` into the fields, each rank its slab of grid g (rank 0
// reads blocks of rows and sends each rank its own). False (on every rank) if rank 0 finds
// one missing or of another shape.
bool read_fields(hid_t where, const char* group, const Grid& g, const std::vector<NamedField<Field>>& fields);

}  // namespace cmc::h5
