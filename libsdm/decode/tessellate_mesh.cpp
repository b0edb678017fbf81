#include "libsdm/decode/tessellate_mesh.h"

#include <opensubdiv/bfr/tessellation.h>

#include <algorithm>
#include <array>
#include <utility>
#include <stdexcept>

namespace sdm {

using OpenSubdiv::Bfr::Parameterization;
using BfrTessellation = OpenSubdiv::Bfr::Tessellation;

namespace {

// The base mesh's edges, numbered: each face side's edge id, and per edge its rate (the larger of its
// two faces', so both sides sample the edge identically). Sorted arrays instead of ordered maps:
// a level-3 decode of 8000 base faces spent a fifth of its time in the maps' lookups.
struct EdgeTable {
  std::vector<int> side_edge;  // 3 per face: the edge of side c (corner c to corner c + 1)
  std::vector<int> rate;       // per edge
};

EdgeTable edge_table(const Eigen::MatrixX3i& base, const std::vector<int>& rate) {
  const int nf = int(base.rows());
  std::vector<std::pair<std::pair<int, int>, int>> sides(3 * size_t(nf));
  for (int f = 0; f < nf; ++f)
    for (int c = 0; c < 3; ++c) sides[3 * size_t(f) + c] = {std::minmax(base(f, c), base(f, (c + 1) % 3)), 3 * f + c};
  std::sort(sides.begin(), sides.end());
  EdgeTable t;
  t.side_edge.resize(sides.size());
  for (size_t i = 0; i < sides.size(); ++i) {
    if (i == 0 || sides[i].first != sides[i - 1].first) t.rate.push_back(1);
    const int e = int(t.rate.size()) - 1, side = sides[i].second;
    t.side_edge[size_t(side)] = e;
    t.rate[size_t(e)] = std::max(t.rate[size_t(e)], rate[size_t(side / 3)]);
  }
  return t;
}

}  // namespace

Tessellation tessellate_mesh(const Eigen::MatrixX3i& base, const std::vector<int>& rate) {
  if (int(rate.size()) != base.rows()) throw std::invalid_argument("tessellate_mesh: one rate per face is needed");
  const EdgeTable edges = edge_table(base, rate);
  // Output points of the base corners (by vertex) and of each edge's inner points (from the
  // edge's smaller vertex), -1 until first made, so that the points keep the order of first use.
  std::vector<int> corner_point(size_t(base.size() ? base.maxCoeff() + 1 : 0), -1);
  std::vector<int> edge_first(edges.rate.size() + 1, 0);
  for (size_t e = 0; e < edges.rate.size(); ++e) edge_first[e + 1] = edge_first[e] + edges.rate[e] - 1;
  std::vector<int> edge_point(size_t(edge_first.back()), -1);

  Tessellation out;
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
    for (int c = 0; c < 3; ++c) rates[c] = edges.rate[size_t(edges.side_edge[3 * size_t(f) + c])];
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
      int& corner = corner_point[size_t(base(f, c))];
      if (corner < 0) corner = new_point(f, coords[2 * k], coords[2 * k + 1]);
      local[k++] = corner;
      const int a = base(f, c), b = base(f, (c + 1) % 3);
      const int e = edges.side_edge[3 * size_t(f) + c];
      const int inner = pattern.GetNumEdgeCoords(c);
      for (int i = 0; i < inner; ++i, ++k) {
        const int from_min = a < b ? i : inner - 1 - i;
        int& p = edge_point[size_t(edge_first[size_t(e)] + from_min)];
        if (p < 0) p = new_point(f, coords[2 * k], coords[2 * k + 1]);
        local[k] = p;
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
