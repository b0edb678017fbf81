#include "libsdm/decode/tessellate_mesh.h"

#include <opensubdiv/bfr/tessellation.h>

#include <map>
#include <stdexcept>

namespace sdm {

using OpenSubdiv::Bfr::Parameterization;
using BfrTessellation = OpenSubdiv::Bfr::Tessellation;

Tessellation tessellate_mesh(const Eigen::MatrixX3i& base, const std::vector<int>& rate) {
  if (int(rate.size()) != base.rows()) throw std::invalid_argument("tessellate_mesh: one rate per face is needed");
  // Edge rate: the larger of the two faces' rates, so both sides sample the edge identically.
  std::map<std::pair<int, int>, int> edge_rate;
  for (int f = 0; f < base.rows(); ++f)
    for (int c = 0; c < 3; ++c) {
      int a = base(f, c), b = base(f, (c + 1) % 3);
      auto key = std::minmax(a, b);
      int& r = edge_rate[{key.first, key.second}];
      r = std::max({r, rate[f], 1});
    }

  Tessellation out;
  std::map<int, int> corner_point;                          // base vertex -> output point
  std::map<std::tuple<int, int, int>, int> edge_point;       // (min, max, index from min) -> output point
  std::vector<std::array<int, 3>> tris;
  const Parameterization tri(OpenSubdiv::Sdc::SCHEME_LOOP, 3);
  std::vector<double> coords;
  std::vector<int> facets, local;

  auto new_point = [&](int f, double u, double v) {
    out.point_face.push_back(f);
    out.point_bary.emplace_back(1.0 - u - v, u, v);
    return int(out.point_face.size()) - 1;
  };

  for (int f = 0; f < base.rows(); ++f) {
    int rates[4];
    for (int c = 0; c < 3; ++c) {
      auto key = std::minmax(base(f, c), base(f, (c + 1) % 3));
      rates[c] = edge_rate[{key.first, key.second}];
    }
    rates[3] = std::max(1, rate[f]);
    BfrTessellation pattern(tri, 4, rates);
    if (!pattern.IsValid()) throw std::runtime_error("tessellate_mesh: invalid tessellation pattern");
    const int n = pattern.GetNumCoords();
    coords.resize(2 * size_t(n));
    pattern.GetCoords(coords.data());
    local.assign(n, -1);
    // Boundary coordinates come first: corner 0, edge 0's inner points, corner 1, edge 1, ...
    int k = 0;
    for (int c = 0; c < 3; ++c) {
      const int vc = base(f, c);
      auto it = corner_point.find(vc);
      if (it == corner_point.end()) it = corner_point.emplace(vc, new_point(f, coords[2 * k], coords[2 * k + 1])).first;
      local[k++] = it->second;
      const int a = base(f, c), b = base(f, (c + 1) % 3);
      const int inner = pattern.GetNumEdgeCoords(c);
      for (int i = 0; i < inner; ++i, ++k) {
        const int from_min = a < b ? i : inner - 1 - i;
        auto key = std::make_tuple(std::min(a, b), std::max(a, b), from_min);
        auto e = edge_point.find(key);
        if (e == edge_point.end()) e = edge_point.emplace(key, new_point(f, coords[2 * k], coords[2 * k + 1])).first;
        local[k] = e->second;
      }
    }
    for (; k < n; ++k) local[k] = new_point(f, coords[2 * k], coords[2 * k + 1]);
    facets.resize(3 * size_t(pattern.GetNumFacets()));
    pattern.GetFacets(facets.data());
    for (size_t t = 0; t < facets.size(); t += 3) {
      tris.push_back({local[facets[t]], local[facets[t + 1]], local[facets[t + 2]]});
      out.triangle_face.push_back(f);
    }
  }
  out.triangles.resize(Eigen::Index(tris.size()), 3);
  for (size_t t = 0; t < tris.size(); ++t) out.triangles.row(Eigen::Index(t)) << tris[t][0], tris[t][1], tris[t][2];
  return out;
}

}  // namespace sdm
