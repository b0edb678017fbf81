#include "libstm/mesh/validate_mesh.h"

#include "libstm/core/errors.h"
#include "libstm/core/union_find.h"
#include "libstm/geometry/differential_geometry.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

namespace sdm {
namespace {

uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (uint64_t(uint32_t(a)) << 32) | uint32_t(b);
}

void add(MeshReport& r, const std::string& kind, long count, const std::string& example, bool fatal,
         const std::string& fix) {
  if (count > 0) r.findings.push_back({kind, count, example, fatal, fix});
}

}  // namespace

bool MeshReport::usable() const {
  return std::none_of(findings.begin(), findings.end(), [](const Finding& f) { return f.fatal; });
}

std::string MeshReport::refusal(const std::string& path) const {
  std::ostringstream s;
  s << "mesh " << path << " cannot go through the pipeline (it needs a 2-manifold triangle mesh that encloses a volume):";
  for (const auto& f : findings)
    if (f.fatal) s << "\n  - " << f.count << " " << f.kind << ", e.g. " << f.example << ". Fix: " << f.fix;
  return s.str();
}

nlohmann::json MeshReport::to_json() const {
  nlohmann::json j;
  j["vertices"] = vertices;
  j["faces"] = faces;
  j["edges"] = edges;
  j["parts"] = parts;
  j["genus_per_part"] = genus_per_part;
  j["faces_per_part"] = faces_per_part;
  j["boundary_loops"] = boundary_loops;
  j["bbox_min"] = {bbox_min.x(), bbox_min.y(), bbox_min.z()};
  j["bbox_max"] = {bbox_max.x(), bbox_max.y(), bbox_max.z()};
  j["usable"] = usable();
  j["findings"] = nlohmann::json::array();
  for (const auto& f : findings)
    j["findings"].push_back({{"kind", f.kind}, {"count", f.count}, {"example", f.example}, {"fatal", f.fatal}, {"fix", f.fix}});
  return j;
}

namespace {

// Counts non-finite coordinates and sets the bounding box of the finite ones; returns the count.
long check_coordinates(const MeshSoup& soup, MeshReport& r) {
  long bad_coord = 0;
  long first_bad = -1;
  r.bbox_min.setConstant(INFINITY);
  r.bbox_max.setConstant(-INFINITY);
  for (long i = 0; i < r.vertices; ++i) {
    if (!soup.points[i].allFinite()) {
      if (first_bad < 0) first_bad = i;
      ++bad_coord;
    } else {
      r.bbox_min = r.bbox_min.cwiseMin(soup.points[i]);
      r.bbox_max = r.bbox_max.cwiseMax(soup.points[i]);
    }
  }
  add(r, "vertices with NaN or infinite coordinates", bad_coord, "vertex " + std::to_string(first_bad), true,
      "remove or repair those vertices in the modelling tool");
  return bad_coord;
}

// Faces that cannot exist in a manifold mesh (a repeated or out-of-range vertex): 0 in the result.
std::vector<char> check_face_indices(const MeshSoup& soup, MeshReport& r) {
  const long nv = r.vertices;
  long invalid = 0;
  std::string invalid_example;
  std::vector<char> face_ok(soup.triangles.size(), 1);
  for (size_t f = 0; f < soup.triangles.size(); ++f) {
    const auto& t = soup.triangles[f];
    bool bad = false;
    for (int v : t)
      if (v < 0 || v >= nv) bad = true;
    if (!bad && (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])) bad = true;
    if (bad) {
      face_ok[f] = 0;
      if (!invalid++) invalid_example = "face " + std::to_string(f);
    }
  }
  add(r, "invalid faces (a repeated or out-of-range vertex index)", invalid, invalid_example, true,
      "remove those faces or merge the duplicated vertices");
  return face_ok;
}

// Duplicated faces: the same three vertices, in either orientation.
void check_duplicated_faces(const MeshSoup& soup, const std::vector<char>& face_ok, MeshReport& r) {
  std::map<std::array<int, 3>, int> seen;
  long dup = 0;
  std::string dup_example;
  for (size_t f = 0; f < soup.triangles.size(); ++f) {
    if (!face_ok[f]) continue;
    auto k = soup.triangles[f];
    std::sort(k.begin(), k.end());
    auto [it, inserted] = seen.emplace(k, int(f));
    if (!inserted) {
      if (!dup++) dup_example = "faces " + std::to_string(it->second) + " and " + std::to_string(f);
    }
  }
  add(r, "duplicated faces", dup, dup_example, true, "delete the duplicates (e.g. 'merge by distance' then 'delete duplicate faces')");
}

uint64_t directed_key(int a, int b) { return (uint64_t(uint32_t(a)) << 32) | uint32_t(b); }

// Edge use of the valid faces.
struct EdgeUse {
  std::unordered_map<uint64_t, std::vector<int>> faces;  // undirected edge (edge_key) -> faces
  std::unordered_map<uint64_t, int> directed;            // directed edge -> uses
};

EdgeUse edge_use(const MeshSoup& soup, const std::vector<char>& face_ok) {
  EdgeUse use;
  use.faces.reserve(soup.triangles.size() * 2);
  for (size_t f = 0; f < soup.triangles.size(); ++f) {
    if (!face_ok[f]) continue;
    const auto& t = soup.triangles[f];
    for (int c = 0; c < 3; ++c) {
      int a = t[c], b = t[(c + 1) % 3];
      use.faces[edge_key(a, b)].push_back(int(f));
      use.directed[directed_key(a, b)]++;
    }
  }
  return use;
}

// Components of the boundary-edge graph.
int count_boundary_loops(std::unordered_map<int, std::vector<int>>& boundary_adj) {
  int loops = 0;
  std::unordered_map<int, char> visited;
  for (const auto& [v, nb] : boundary_adj) {
    if (visited[v]) continue;
    ++loops;
    std::vector<int> stack{v};
    visited[v] = 1;
    while (!stack.empty()) {
      int x = stack.back();
      stack.pop_back();
      for (int y : boundary_adj[x])
        if (!visited[y]) visited[y] = 1, stack.push_back(y);
    }
  }
  return loops;
}

// Boundary edges (and loops), non-manifold edges, edges between inconsistently oriented faces.
void check_edges(const EdgeUse& use, MeshReport& r) {
  r.edges = long(use.faces.size());
  long boundary = 0, nonmanifold = 0, flipped = 0;
  std::string boundary_example, nm_example, flip_example;
  std::unordered_map<int, std::vector<int>> boundary_adj;
  for (const auto& [k, fs] : use.faces) {
    int a = int(k >> 32), b = int(k & 0xffffffffu);
    std::string e = "edge (" + std::to_string(a) + ", " + std::to_string(b) + ")";
    if (fs.size() == 1) {
      if (!boundary++) boundary_example = e + " of face " + std::to_string(fs[0]);
      boundary_adj[a].push_back(b);
      boundary_adj[b].push_back(a);
    } else if (fs.size() > 2) {
      if (!nonmanifold++) nm_example = e + " shared by " + std::to_string(fs.size()) + " faces";
    } else {
      auto ab = use.directed.find(directed_key(a, b));
      if (ab != use.directed.end() && ab->second != 1) {
        if (!flipped++) flip_example = "faces " + std::to_string(fs[0]) + " and " + std::to_string(fs[1]) + " across " + e;
      }
    }
  }
  r.boundary_loops = count_boundary_loops(boundary_adj);
  add(r, "boundary edges (the mesh is open)", boundary,
      boundary_example + "; " + std::to_string(r.boundary_loops) + " boundary loop(s)", false,
      "nothing to fix: the skeleton is computed with the holes filled and every output keeps them open; "
      "--fill-holes closes them in the output instead");
  add(r, "non-manifold edges", nonmanifold, nm_example, true,
      "split the mesh where more than two faces meet at an edge, or remove the extra faces");
  add(r, "edges between inconsistently oriented faces", flipped, flip_example, true,
      "recompute consistent normals (e.g. 'recalculate outside' in Blender)");
}

// The number of fans the faces `fs` around vertex v form: faces are connected when they share an
// edge that contains v.
int fans_around(const MeshSoup& soup, int v, const std::vector<int>& fs) {
  std::unordered_map<int, std::vector<int>> by_other;  // other vertex -> faces
  for (size_t i = 0; i < fs.size(); ++i)
    for (int w : soup.triangles[fs[i]])
      if (w != v) by_other[w].push_back(int(i));
  UnionFind uf(fs.size());
  for (const auto& [w, list] : by_other)
    for (size_t i = 1; i < list.size(); ++i) uf.unite(list[0], list[i]);
  return uf.count();
}

// Non-manifold vertices: incident faces must form a single fan (connected through edges at the vertex).
void check_vertex_fans(const MeshSoup& soup, const std::vector<char>& face_ok, MeshReport& r) {
  const long nv = r.vertices;
  long nm_vertices = 0;
  std::string nmv_example;
  std::vector<std::vector<int>> vf(nv);
  for (size_t f = 0; f < soup.triangles.size(); ++f)
    if (face_ok[f])
      for (int v : soup.triangles[f]) vf[v].push_back(int(f));
  for (long v = 0; v < nv; ++v) {
    if (vf[v].size() < 2) continue;
    const int roots = fans_around(soup, int(v), vf[v]);
    if (roots > 1) {
      if (!nm_vertices++) nmv_example = "vertex " + std::to_string(v) + " where " + std::to_string(roots) + " fans of faces meet";
    }
  }
  add(r, "non-manifold vertices", nm_vertices, nmv_example, true,
      "split the vertex so that each fan of faces gets its own copy (e.g. 'split non-manifold vertices' in MeshLab)");
}

// Degenerate faces: harmless for I/O, reported because they make the Laplacian ill-conditioned.
// Only measured when every coordinate is finite.
void check_degenerate_faces(const MeshSoup& soup, const std::vector<char>& face_ok, long bad_coord, MeshReport& r) {
  const double diag = (r.bbox_max - r.bbox_min).norm();
  long degenerate = 0;
  std::string deg_example;
  const double area_eps = 1e-14 * diag * diag;
  for (size_t f = 0; f < soup.triangles.size(); ++f) {
    if (!face_ok[f] || bad_coord) continue;
    const auto& t = soup.triangles[f];
    const double a = triangle_area(soup.points[t[0]], soup.points[t[1]], soup.points[t[2]]);
    if (a <= area_eps) {
      if (!degenerate++) deg_example = "face " + std::to_string(f);
    }
  }
  add(r, "degenerate (zero-area) faces", degenerate, deg_example, false,
      "they are tolerated; remove them for better skeletons (e.g. 'remove zero-area faces' in MeshLab)");
}

void check_isolated_vertices(const MeshSoup& soup, const std::vector<char>& face_ok, MeshReport& r) {
  const long nv = r.vertices;
  std::vector<char> used(nv, 0);
  for (size_t f = 0; f < soup.triangles.size(); ++f)
    if (face_ok[f])
      for (int v : soup.triangles[f]) used[v] = 1;
  long isolated = 0;
  std::string iso_example;
  for (long v = 0; v < nv; ++v)
    if (!used[v] && !isolated++) iso_example = "vertex " + std::to_string(v);
  add(r, "isolated vertices (in no face)", isolated, iso_example, false, "they are ignored; delete loose vertices to silence this");
}

// Parts and genus: Euler characteristic per edge-connected component.
void find_parts(const MeshSoup& soup, const std::vector<char>& face_ok, const EdgeUse& use, MeshReport& r) {
  const long nv = r.vertices;
  UnionFind uf(soup.triangles.size());
  for (const auto& [k, fs] : use.faces)
    for (size_t i = 1; i < fs.size(); ++i) uf.unite(fs[0], fs[i]);
  std::map<int, int> part_of_root;
  r.face_part.assign(soup.triangles.size(), -1);
  for (size_t f = 0; f < soup.triangles.size(); ++f) {
    if (!face_ok[f]) continue;
    int root = uf.find(int(f));
    auto it = part_of_root.emplace(root, int(part_of_root.size())).first;
    r.face_part[f] = it->second;
  }
  r.parts = int(part_of_root.size());
  std::vector<long> pv(r.parts, 0), pe(r.parts, 0), pf(r.parts, 0), pb(r.parts, 0);
  std::vector<int> vpart(nv, -1);
  for (size_t f = 0; f < soup.triangles.size(); ++f) {
    if (r.face_part[f] < 0) continue;
    pf[r.face_part[f]]++;
    for (int v : soup.triangles[f]) vpart[v] = r.face_part[f];
  }
  for (long v = 0; v < nv; ++v)
    if (vpart[v] >= 0) pv[vpart[v]]++;
  // Boundary loops per part: components of its boundary edges (one loop per component, since
  // non-manifold vertices, where two loops would touch, are refused).
  UnionFind loops{static_cast<size_t>(nv)};
  std::vector<char> on_boundary(size_t(nv), 0);
  for (const auto& [k, fs] : use.faces) {
    pe[r.face_part[fs[0]]]++;
    if (fs.size() != 1) continue;
    const int a = int(k >> 32), b = int(k & 0xffffffffu);
    loops.unite(a, b);
    on_boundary[size_t(a)] = on_boundary[size_t(b)] = 1;
  }
  for (long v = 0; v < nv; ++v)
    if (on_boundary[size_t(v)] && loops.find(int(v)) == int(v) && vpart[v] >= 0) pb[vpart[v]]++;
  r.boundary_loops_per_part.assign(size_t(r.parts), 0);
  for (int p = 0; p < r.parts; ++p) {
    // Genus of the closed surface the part becomes with each loop capped by a disc.
    const long chi = pv[p] - pe[p] + pf[p] + pb[p];
    r.genus_per_part.push_back(int((2 - chi) / 2));
    r.faces_per_part.push_back(int(pf[p]));
    r.boundary_loops_per_part[size_t(p)] = int(pb[p]);
  }
  if (r.parts > 1)
    add(r, "connected parts", r.parts, "each part gets its own skeleton", false, "nothing to fix: several parts are supported");
}

// Signed volume of every part (faces with face_part -1 left out), each hole capped by a cone from
// the mean of its part's boundary vertices so that open parts have one too; measured from a vertex
// of the part (no cancellation far from (0, 0, 0)).
std::vector<double> part_volumes(const MeshSoup& soup, const std::vector<int>& face_part, int parts) {
  std::unordered_set<uint64_t> edges;
  for (size_t f = 0; f < soup.triangles.size(); ++f)
    if (face_part[f] >= 0)
      for (int c = 0; c < 3; ++c) edges.insert(directed_key(soup.triangles[f][c], soup.triangles[f][(c + 1) % 3]));
  std::vector<double> volume(size_t(parts), 0.0);
  std::vector<int> origin(size_t(parts), -1);
  std::vector<Eigen::Vector3d> apex(size_t(parts), Eigen::Vector3d::Zero());
  std::vector<long> rim(size_t(parts), 0);
  std::vector<std::array<int, 3>> caps;  // (b, a, part) for face edges a -> b without an opposite
  auto tet = [&](int p, const Eigen::Vector3d& x, const Eigen::Vector3d& y, const Eigen::Vector3d& z) {
    const Eigen::Vector3d& o = soup.points[size_t(origin[size_t(p)])];
    volume[size_t(p)] += (x - o).dot((y - o).cross(z - o)) / 6.0;
  };
  for (size_t f = 0; f < soup.triangles.size(); ++f) {
    const int p = face_part[f];
    if (p < 0) continue;
    const auto& t = soup.triangles[f];
    if (origin[size_t(p)] < 0) origin[size_t(p)] = t[0];
    tet(p, soup.points[t[0]], soup.points[t[1]], soup.points[t[2]]);
    for (int c = 0; c < 3; ++c) {
      const int a = t[c], b = t[(c + 1) % 3];
      if (edges.count(directed_key(b, a))) continue;
      caps.push_back({b, a, p});
      apex[size_t(p)] += soup.points[size_t(a)], ++rim[size_t(p)];
    }
  }
  for (const auto& [b, a, p] : caps) tet(p, soup.points[size_t(b)], soup.points[size_t(a)], apex[size_t(p)] / double(rim[size_t(p)]));
  return volume;
}

// A part whose signed volume is nought (its holes capped) is flat (both sides of one sheet, folded
// onto itself, or an open sheet): no capsule sees its surface from inside, and an encode of it is
// garbage with a success code (issue 15: 0 % of texels on their own surface). Relative to the
// part's own bounding box, so that it holds at any scale. Only for usable input.
void check_volumes(const MeshSoup& soup, const std::vector<char>& face_ok, MeshReport& r) {
  if (!r.usable() || r.parts == 0) return;
  std::vector<int> face_part = r.face_part;
  for (size_t f = 0; f < face_part.size(); ++f)
    if (!face_ok[f]) face_part[f] = -1;
  const std::vector<double> volume = part_volumes(soup, face_part, r.parts);
  std::vector<Eigen::Vector3d> lo(r.parts, Eigen::Vector3d::Constant(INFINITY)), hi(r.parts, Eigen::Vector3d::Constant(-INFINITY));
  for (size_t f = 0; f < soup.triangles.size(); ++f)
    if (face_part[f] >= 0)
      for (int v : soup.triangles[f]) lo[face_part[f]] = lo[face_part[f]].cwiseMin(soup.points[v]), hi[face_part[f]] = hi[face_part[f]].cwiseMax(soup.points[v]);
  long flat = 0;
  std::string example;
  for (int p = 0; p < r.parts; ++p) {
    const double d = (hi[p] - lo[p]).norm();
    if (std::abs(volume[p]) <= 1e-9 * d * d * d && !flat++)
      example = "part " + std::to_string(p) + " (" + std::to_string(r.faces_per_part[p]) + " faces) has volume " + number(volume[p]) +
                " within a box of diagonal " + number(d);
  }
  add(r, "parts enclosing no volume (flat: both sides of one sheet, or an open sheet)", flat, example, true,
      "give the part a thickness (e.g. 'solidify' in Blender); a surface mapped from a skeleton needs an inside");
}

}  // namespace

MeshReport validate_mesh(const MeshSoup& soup) {
  MeshReport r;
  r.vertices = long(soup.points.size());
  r.faces = long(soup.triangles.size());
  if (soup.triangles.empty()) {
    add(r, "empty mesh (no faces)", 1, std::to_string(r.vertices) + " vertices but no face", true,
        "export the surface as triangles or polygons, not as points or lines");
    return r;
  }
  // The findings come in this order: fatal ones first, from coordinates to topology.
  const long bad_coord = check_coordinates(soup, r);
  const std::vector<char> face_ok = check_face_indices(soup, r);
  check_duplicated_faces(soup, face_ok, r);
  const EdgeUse use = edge_use(soup, face_ok);
  check_edges(use, r);
  check_vertex_fans(soup, face_ok, r);
  check_degenerate_faces(soup, face_ok, bad_coord, r);
  check_isolated_vertices(soup, face_ok, r);
  find_parts(soup, face_ok, use, r);
  check_volumes(soup, face_ok, r);
  if (soup.polygons_triangulated)
    add(r, "polygons triangulated on read (ear clipping)", soup.polygons_triangulated, "faces with more than three corners", false,
        "nothing to fix; triangulate in the modelling tool for control over the diagonals");
  return r;
}

void orient_outward(MeshSoup& soup, MeshReport& report) {
  const std::vector<double> volume = part_volumes(soup, report.face_part, report.parts);
  long flipped = 0;
  int example = -1;
  for (size_t f = 0; f < soup.triangles.size(); ++f) {
    if (volume[report.face_part[f]] >= 0) continue;
    std::swap(soup.triangles[f][1], soup.triangles[f][2]);
    if (!soup.uv.empty()) std::swap(soup.uv[3 * f + 1], soup.uv[3 * f + 2]);
    if (example < 0) example = report.face_part[f];
    ++flipped;
  }
  if (flipped)
    report.findings.push_back({"faces flipped to point outwards", flipped, "part " + std::to_string(example) + " was inside out",
                               false, "nothing to fix; the input's normals pointed inwards"});
}

}  // namespace sdm
