#pragma once
// What convert and repair share: a mesh read as every command reads it and written in another format.
#include "libstm/mesh/load_mesh.h"

#include <string>

namespace sdm::cli {

// Reads, repairs (unless --no-repair or --strict), validates and writes; returns what happened and,
// in `rounding`, what a float32 format's rounding cost (note_float32_rounding).
sdm::LoadReport convert(const std::string& in, const std::string& out, bool strict, double& rounding);

}  // namespace sdm::cli
