#include "apps/decoded_mesh.h"

#include "apps/options.h"
#include "libsdm/pose/rig_skin.h"
#include "libstm/core/errors.h"
#include "libstm/mesh/gltf_skin.h"
#include "libstm/mesh/validate_mesh.h"

#include <algorithm>
#include <iostream>

namespace sdm::cli {

SurfaceTopology topology_of(const sdm::Mesh& m) {
  const sdm::MeshReport r = sdm::validate_mesh(sdm::mesh_to_soup(m));
  SurfaceTopology t{r.usable(), r.boundary_loops, 0};
  for (int g : r.genus_per_part) t.genus += g;
  return t;
}

void check_decode_memory(const sdm::SdmImage& im, const sdm::DecodeOptions& d, const std::string& max_memory) {
  const sdm::DecodeEstimate e = sdm::estimate_decode(im, d);
  check_memory(e.bytes, max_memory, "decoding " + std::to_string(int64_t(e.triangles / 1e6)) + " million triangles",
               "use a lower --lod (each level quadruples the triangles)");
}

void check_rig_output(const std::string& out) {
  if (!has_extension(out, {".glb", ".gltf"}))
    throw sdm::InputError("--rig writes a glTF skin: the output must be .glb or .gltf, not '" + out + "'");
}

void write_rigged(const sdm::Mesh& mesh, const sdm::Layout& layout, const sdm::DecodeTrace& trace, const sdm::PosedSkeleton* posed,
                  const std::string& out) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices()) points.push_back(sdm::point(mesh, v));
  if (posed && std::any_of(posed->segment_radius_scale.begin(), posed->segment_radius_scale.end(), [](double f) { return f != 1.0; }))
    std::cerr << "warning: --rig writes a glTF skin, which carries joint motions only: the radius scales are left out of "
              << out << " (write a mesh without --rig to keep them)\n";
  sdm::write_gltf_skinned(mesh, sdm::rig_skin(layout, points, trace.vertex_segment, sdm::face_matrix(mesh), posed), out);
}

}  // namespace sdm::cli
