#include "libstm/layout/stm_coordinates.h"

#include "libstm/layout/assign_layout_faces.h"
#include "libstm/layout/atlas_triangles.h"
#include "libstm/layout/l2_stretch.h"

namespace sdm {

StmCoordinates stm_coordinates(const Mesh& mesh, const Layout& L, const std::vector<int>& face_segment) {
  StmCoordinates r;
  r.face_segment = face_segment.size() == mesh.n_faces() ? face_segment : assign_faces(mesh, L);
  r.mesh = mesh;
  r.mesh.request_halfedge_texcoords2D();
  const std::vector<AtlasTriangle> tris = atlas_triangles(mesh, L, r.face_segment);
  for (const auto& t : tris) {
    if (t.copy != 0) {
      ++r.seam_faces;
      continue;
    }
    const auto f = r.mesh.face_handle(t.face);
    // Corners in fv order, as atlas_triangles takes them.
    int k = 0;
    for (auto v : r.mesh.fv_range(f)) {
      for (auto h : r.mesh.fh_range(f))
        if (r.mesh.to_vertex_handle(h) == v)
          r.mesh.set_texcoord2D(h, Mesh::TexCoord2D(t.atlas[k].x() / L.size, t.atlas[k].y() / L.size));
      ++k;
    }
  }
  r.coverage = L.coverage;
  r.stretch = l2_stretch(r.mesh);
  return r;
}

}  // namespace sdm
