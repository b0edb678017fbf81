#pragma once
// What decode, pose and roundtrip share about the mesh a map decodes to: its topology, and the
// glTF skin --rig writes.
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/map/sdm_exr.h"
#include "libstm/layout/layout.h"
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/posed_skeleton.h"

#include <string>

namespace sdm::cli {

// What a decoded surface is: 2-manifold (usable by the pipeline again), with how many boundary
// loops (those of an open input's holes; 0 for a closed one) and handles (the genus of its parts).
struct SurfaceTopology {
  bool manifold = false;
  int boundary_loops = 0;
  int genus = 0;
  bool closed() const { return manifold && boundary_loops == 0; }
  std::string text() const {
    if (!manifold) return "NOT manifold";
    return boundary_loops ? "2-manifold with " + std::to_string(boundary_loops) + " boundary loop(s)" : "closed 2-manifold";
  }
};

SurfaceTopology topology_of(const sdm::Mesh& m);

// Refuses (InputError), before the work, a decode whose estimate (estimate_decode) exceeds the
// memory budget (--max-memory), naming its triangles and --lod.
void check_decode_memory(const sdm::SdmImage& im, const sdm::DecodeOptions& d, const std::string& max_memory);

// --rig writes a skin, which only glTF carries: InputError for another output format.
void check_rig_output(const std::string& out);

// Writes `mesh` (decoded at rest, `trace` its decode's) to `out` rigged by rig_skin: the bind pose
// is the map's own skeleton; `posed`, when given, is the pose the file opens in.
void write_rigged(const sdm::Mesh& mesh, const sdm::Layout& layout, const sdm::DecodeTrace& trace, const sdm::PosedSkeleton* posed,
                  const std::string& out);

}  // namespace sdm::cli
