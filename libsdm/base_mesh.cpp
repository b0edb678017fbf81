#include "libsdm/base_mesh.h"

#include "libstm/errors.h"
#include "libstm/segments.h"

#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

namespace stm {

BaseMesh make_base_mesh(const Mesh& mesh, const Layout& layout, int target_vertices) {
  const int nv = int(mesh.n_vertices());
  if (target_vertices <= 0) target_vertices = std::clamp(nv / 4, std::min(nv, 400), 4000);
  Mesh m = mesh;
  OpenMesh::VPropHandleT<int> original;
  m.add_property(original);
  for (auto v : m.vertices()) m.property(original, v) = v.idx();
  if (target_vertices < nv) {
    m.request_face_normals();
    m.update_face_normals();
    OpenMesh::Decimater::DecimaterT<Mesh> decimater(m);
    OpenMesh::Decimater::ModQuadricT<Mesh>::Handle quadric;
    OpenMesh::Decimater::ModNormalFlippingT<Mesh>::Handle flipping;
    decimater.add(quadric);
    decimater.add(flipping);
    decimater.module(quadric).unset_max_err();
    decimater.module(flipping).set_max_normal_deviation(60.0);
    decimater.initialize();
    decimater.decimate_to(size_t(target_vertices));
    m.garbage_collection();
  }
  // Segments of the base faces: the skeleton's map restricted to the surviving vertices.
  Skeleton sk = layout.skeleton;
  sk.vertex_node.resize(m.n_vertices());
  for (auto v : m.vertices()) sk.vertex_node[v.idx()] = layout.skeleton.vertex_node[m.property(original, v)];
  BaseMesh base;
  base.face_segment = assign_faces(m, sk);
  base.triangles = face_matrix(m);
  base.corner_uv.resize(m.n_faces());
  base.corner_position.resize(m.n_faces());
  for (auto f : m.faces()) {
    const int s = base.face_segment[f.idx()];
    const LayoutSegment& seg = layout.segments[s];
    const CapsuleFrame frame = capsule_frame(layout, s);
    int c = 0;
    for (auto v : m.fv_range(f)) {
      const Eigen::Vector3d p = point(mesh, mesh.vertex_handle(m.property(original, v)));
      const CapsuleUV uv = capsule_uv(frame, seg.w, seg.h, seg.d, p);
      base.corner_position[f.idx()][c] = p;
      base.corner_uv[f.idx()][c++] = {uv.u, uv.v};
    }
  }
  return base;
}

nlohmann::json base_mesh_to_json(const BaseMesh& base) {
  nlohmann::json j;
  std::vector<int> tris;
  std::vector<double> uv;
  for (int f = 0; f < base.triangles.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      tris.push_back(base.triangles(f, c));
      uv.push_back(base.corner_uv[f][c].x());
      uv.push_back(base.corner_uv[f][c].y());
    }
  j["triangles"] = tris;
  j["face_segment"] = base.face_segment;
  j["corner_uv"] = uv;
  return j;
}

BaseMesh base_mesh_from_json(const nlohmann::json& j, int segments) {
  BaseMesh base;
  std::vector<int> tris;
  std::vector<double> uv;
  try {
    tris = j.at("triangles").get<std::vector<int>>();
    base.face_segment = j.at("face_segment").get<std::vector<int>>();
    uv = j.at("corner_uv").get<std::vector<double>>();
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("invalid base mesh in the SDM header: ") + e.what());
  }
  const size_t nf = base.face_segment.size();
  if (tris.size() != 3 * nf || uv.size() != 6 * nf || nf == 0)
    throw InputError("invalid base mesh in the SDM header: " + std::to_string(nf) + " faces but " +
                     std::to_string(tris.size()) + " corner indices and " + std::to_string(uv.size()) + " uv values");
  base.triangles.resize(Eigen::Index(nf), 3);
  base.corner_uv.resize(nf);
  for (size_t f = 0; f < nf; ++f) {
    if (base.face_segment[f] < 0 || base.face_segment[f] >= segments)
      throw InputError("invalid base mesh in the SDM header: face " + std::to_string(f) + " names segment " +
                       std::to_string(base.face_segment[f]) + " of " + std::to_string(segments));
    for (int c = 0; c < 3; ++c) {
      if (tris[3 * f + c] < 0) throw InputError("invalid base mesh in the SDM header: negative vertex index");
      base.triangles(Eigen::Index(f), c) = tris[3 * f + c];
      base.corner_uv[f][c] = {uv[6 * f + 2 * c], uv[6 * f + 2 * c + 1]};
    }
  }
  return base;
}

}  // namespace stm
