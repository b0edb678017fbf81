#include "libstm/mesh/mesh_geometry.h"

namespace sdm {

std::vector<double> vertex_areas(const Mesh& m, double factor) {
  std::vector<double> a(m.n_vertices(), 0.0);
  for (auto f : m.faces()) {
    const double x = m.calc_face_area(f) * factor / 3;
    for (auto v : m.fv_range(f)) a[v.idx()] += x;
  }
  return a;
}

}  // namespace sdm
