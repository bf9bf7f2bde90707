// A run's result files (Writer.hpp): each step's fields and observables in a file of its own
// while the run goes on, then result.h5 (the heights and every step's group) and result.xdmf
// (the pointer file ParaView opens) when it finishes. A run without fields but with
// observables still gets result.h5, with the steps' observables alone: the distributions of a
// grid too large to carry its fields. Internal to the output layer.
#pragma once

#include "cmc/run/Driver.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace cmc {

// The attributes and observables of step `rec`, and its fields when `fields`, into the new
// HDF5 file `tmp` (group step_NNNN). In a distributed run every rank calls it with its
// slabs; rank 0 writes (`tmp` is its).
void write_step_file(const std::filesystem::path& tmp, const StepRecord& rec, const ContactState& st, const Scene& s,
                     bool fields);
// result.h5 into the new file `tmp` (rank 0): the heights when `fields`, then every step's
// group copied from its file, step_files[k] for steps[k].
void write_result_file(const std::filesystem::path& tmp, const Case& c, const Scene& s,
                       const std::vector<StepRecord>& steps, const std::vector<std::filesystem::path>& step_files,
                       bool fields);
// The XDMF pointer file for ParaView: one 2-D uniform grid per step, its fields in result.h5.
std::string xdmf_text(const std::vector<StepRecord>& steps, const Scene& s);

}  // namespace cmc
