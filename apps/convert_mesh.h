#pragma once
// What convert and repair share: a mesh read as every command reads it and written in another format.
#include "libstm/mesh/load_mesh.h"

#include <nlohmann/json.hpp>
#include <string>

namespace sdm::cli {

// What convert did: the load's report, what a float32 format's rounding cost (note_float32_rounding)
// and the counts of the mesh written.
struct Converted {
  sdm::LoadReport report;
  double rounding = 0;
  size_t vertices = 0, faces = 0;
};

// Reads, repairs (unless --no-repair or --strict), validates and writes; returns what happened.
Converted convert(const std::string& in, const std::string& out, bool strict);

// The line convert and repair print (stderr) for the mesh written: their summary's "output",
// "vertices" and "faces".
void print_written(const nlohmann::json& summary);

}  // namespace sdm::cli
