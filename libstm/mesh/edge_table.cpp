#include "libstm/mesh/edge_table.h"

#include <algorithm>
#include <cstdint>

namespace sdm {

EdgeTable edge_table(const std::vector<std::array<int, 3>>& triangles, size_t vertices, const std::vector<char>& use) {
  const size_t nv = vertices, nf = triangles.size();
  auto used = [&](size_t f) { return use.empty() || use[f]; };
  std::vector<size_t> start(nv + 1, 0);
  for (size_t f = 0; f < nf; ++f)
    if (used(f))
      for (int c = 0; c < 3; ++c) ++start[size_t(std::min(triangles[f][c], triangles[f][(c + 1) % 3])) + 1];
  for (size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  const size_t n = start[nv];
  std::vector<uint64_t> entry(n);  // (larger vertex << 32) | 3 f + c
  std::vector<size_t> fill(start.begin(), start.end() - 1);
  for (size_t f = 0; f < nf; ++f) {
    if (!used(f)) continue;
    for (int c = 0; c < 3; ++c) {
      const int a = triangles[f][c], b = triangles[f][(c + 1) % 3];
      entry[fill[size_t(std::min(a, b))]++] = (uint64_t(uint32_t(std::max(a, b))) << 32) | uint64_t(3 * f + size_t(c));
    }
  }
  EdgeTable t;
  t.lo.resize(n), t.hi.resize(n), t.halfedge.resize(n), t.forward.resize(n);
  t.group.reserve(n / 2 + 2);
  for (size_t v = 0; v < nv; ++v) {
    std::sort(entry.begin() + long(start[v]), entry.begin() + long(start[v + 1]));
    for (size_t i = start[v]; i < start[v + 1]; ++i) {
      const size_t h = size_t(entry[i] & 0xffffffffu);
      t.lo[i] = int(v), t.hi[i] = int(entry[i] >> 32), t.halfedge[i] = int(h);
      t.forward[i] = triangles[h / 3][h % 3] == int(v);
      if (i == start[v] || t.hi[i] != t.hi[i - 1]) t.group.push_back(i);
    }
  }
  t.group.push_back(n);
  return t;
}

EdgeTable without_faces(const EdgeTable& t, const std::vector<int>& index) {
  EdgeTable out;
  const size_t n = t.halfedge.size();
  out.lo.reserve(n), out.hi.reserve(n), out.halfedge.reserve(n), out.forward.reserve(n), out.group.reserve(t.group.size());
  for (size_t e = 0; e < t.edges(); ++e) {
    const size_t first = out.halfedge.size();
    for (size_t i = t.group[e]; i < t.group[e + 1]; ++i) {
      const int f = index[size_t(t.face(i))];
      if (f < 0) continue;
      out.lo.push_back(t.lo[i]), out.hi.push_back(t.hi[i]), out.forward.push_back(t.forward[i]);
      out.halfedge.push_back(3 * f + t.halfedge[i] % 3);
    }
    if (out.halfedge.size() > first) out.group.push_back(first);
  }
  out.group.push_back(out.halfedge.size());
  return out;
}

std::vector<std::array<int, 3>> boundary_halfedges(const EdgeTable& t) {
  std::vector<std::array<int, 3>> out;
  for (size_t e = 0; e < t.edges(); ++e) {
    if (t.uses(e) != 1) continue;
    const size_t i = t.group[e];
    out.push_back(t.forward[i] ? std::array<int, 3>{t.lo[i], t.hi[i], t.face(i)} : std::array<int, 3>{t.hi[i], t.lo[i], t.face(i)});
  }
  return out;
}

}  // namespace sdm
