#include "libstm/mesh/validate_mesh.h"

#include "libstm/mesh/edge_table.h"

#include "libstm/core/errors.h"
#include "libstm/core/parallel.h"
#include "libstm/core/union_find.h"
#include "libstm/geometry/differential_geometry.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>
#include <numeric>

namespace sdm {
namespace {

void add(MeshReport& r, const std::string& id, const std::string& kind, long count, const std::string& example, bool fatal,
         const std::string& fix) {
  if (count > 0) r.findings.push_back({id, kind, count, example, fatal, fix});
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
    j["findings"].push_back(
        {{"id", f.id}, {"kind", f.kind}, {"count", f.count}, {"example", f.example}, {"fatal", f.fatal}, {"fix", f.fix}});
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
  add(r, "bad_coordinates", "vertices with NaN or infinite coordinates", bad_coord, "vertex " + std::to_string(first_bad), true,
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
  add(r, "invalid_faces", "invalid faces (a repeated or out-of-range vertex index)", invalid, invalid_example, true,
      "remove those faces or merge the duplicated vertices");
  return face_ok;
}

// Duplicated faces: the same three vertices, in either orientation. The faces sorted by their
// sorted corners (linear memory, no node per face); the example is the lowest-numbered face that
// repeats an earlier one, with that earlier one.
void check_duplicated_faces(const MeshSoup& soup, const std::vector<char>& face_ok, MeshReport& r) {
  std::vector<std::pair<std::array<int, 3>, int>> sorted;
  sorted.reserve(soup.triangles.size());
  for (size_t f = 0; f < soup.triangles.size(); ++f) {
    if (!face_ok[f]) continue;
    auto k = soup.triangles[f];
    std::sort(k.begin(), k.end());
    sorted.push_back({k, int(f)});
  }
  std::sort(sorted.begin(), sorted.end());
  long dup = 0;
  int first = -1, repeat = -1;
  size_t g = 0;  // the current group's first (lowest-numbered) face
  for (size_t i = 1; i < sorted.size(); ++i) {
    if (sorted[i].first != sorted[i - 1].first) {
      g = i;
      continue;
    }
    ++dup;
    if (repeat < 0 || sorted[i].second < repeat) repeat = sorted[i].second, first = sorted[g].second;
  }
  add(r, "duplicated_faces", "duplicated faces", dup,
      dup ? "faces " + std::to_string(first) + " and " + std::to_string(repeat) : "", true,
      "delete the duplicates (e.g. 'merge by distance' then 'delete duplicate faces')");
}


// Components of the boundary-edge graph (a loop each, since non-manifold vertices are refused).
int count_boundary_loops(const EdgeTable& t, size_t vertices) {
  UnionFind uf(vertices);
  std::vector<char> on(vertices, 0);
  for (size_t e = 0; e < t.edges(); ++e)
    if (t.uses(e) == 1) {
      const size_t i = t.group[e];
      uf.unite(t.lo[i], t.hi[i]), on[size_t(t.lo[i])] = on[size_t(t.hi[i])] = 1;
    }
  int loops = 0;
  for (size_t v = 0; v < vertices; ++v) loops += on[v] && uf.find(int(v)) == int(v);
  return loops;
}

// Boundary edges (and loops), non-manifold edges, edges between inconsistently oriented faces.
// Returns whether any edge is on a border, crowded or between inconsistently oriented faces.
bool check_edges(const EdgeTable& t, size_t vertices, MeshReport& r) {
  r.edges = long(t.edges());
  long boundary = 0, nonmanifold = 0, flipped = 0;
  std::string boundary_example, nm_example, flip_example;
  for (size_t e = 0; e < t.edges(); ++e) {
    const size_t i = t.group[e], uses = t.uses(e);
    auto name = [&]() { return "edge (" + std::to_string(t.lo[i]) + ", " + std::to_string(t.hi[i]) + ")"; };
    if (uses == 1) {
      if (!boundary++) boundary_example = name() + " of face " + std::to_string(t.face(i));
    } else if (uses > 2) {
      if (!nonmanifold++) nm_example = name() + " shared by " + std::to_string(uses) + " faces";
    } else if (t.forward[i] == t.forward[i + 1]) {
      if (!flipped++) flip_example = "faces " + std::to_string(t.face(i)) + " and " + std::to_string(t.face(i + 1)) + " across " + name();
    }
  }
  r.boundary_loops = boundary ? count_boundary_loops(t, vertices) : 0;
  add(r, "boundary_edges", "boundary edges (the mesh is open)", boundary,
      boundary_example + "; " + std::to_string(r.boundary_loops) + " boundary loop(s)", false,
      "nothing to fix: the skeleton is computed with the holes filled and every output keeps them open; "
      "--fill-holes closes them in the output instead");
  add(r, "non_manifold_edges", "non-manifold edges", nonmanifold, nm_example, true,
      "split the mesh where more than two faces meet at an edge, or remove the extra faces");
  add(r, "inconsistent_orientation", "edges between inconsistently oriented faces", flipped, flip_example, true,
      "recompute consistent normals (e.g. 'recalculate outside' in Blender)");
  return boundary || nonmanifold || flipped;
}

// The number of fans of faces around each vertex in [from, to) (faces connected through an edge at
// the vertex): up to 32 faces, a walk over the faces that share one of their two other corners
// (bit sets, no allocation: a third of the time of sorting); more, each vertex's faces' other
// corners sorted, so that faces sharing an edge at the vertex meet (d log d for a vertex in d
// faces, whatever d). `start`/`vf`: the faces per vertex.
void count_fans(const MeshSoup& soup, const std::vector<size_t>& start, const std::vector<int>& vf, size_t from, size_t to,
                std::vector<int>& fans) {
  std::vector<std::pair<int, int>> other;  // (other corner, local face index)
  std::vector<int> parent;
  int a[32], b[32];
  for (size_t v = from; v < to; ++v) {
    const size_t d = start[v + 1] - start[v];
    if (d < 2) continue;
    if (d <= 32) {
      for (size_t i = 0; i < d; ++i) {
        const auto& t = soup.triangles[size_t(vf[start[v] + i])];
        const int c = t[0] == int(v) ? 0 : t[1] == int(v) ? 1 : 2;
        a[i] = t[(c + 1) % 3], b[i] = t[(c + 2) % 3];
      }
      uint32_t left = d == 32 ? ~0u : (1u << d) - 1;
      int count = 0;
      while (left) {
        uint32_t frontier = left & (~left + 1);
        left &= ~frontier, ++count;
        while (frontier) {
          const int i = __builtin_ctz(frontier);
          frontier &= frontier - 1;
          for (uint32_t m = left; m; m &= m - 1) {
            const int j = __builtin_ctz(m);
            if (a[i] == a[j] || a[i] == b[j] || b[i] == a[j] || b[i] == b[j]) left &= ~(1u << j), frontier |= 1u << j;
          }
        }
      }
      fans[v] = count;
      continue;
    }
    other.clear();
    for (size_t i = 0; i < d; ++i)
      for (int w : soup.triangles[size_t(vf[start[v] + i])])
        if (w != int(v)) other.push_back({w, int(i)});
    std::sort(other.begin(), other.end());
    parent.resize(d);
    std::iota(parent.begin(), parent.end(), 0);
    auto root = [&](int x) {
      while (parent[size_t(x)] != x) x = parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
      return x;
    };
    int count = int(d);
    for (size_t k = 1; k < other.size(); ++k)
      if (other[k].first == other[k - 1].first) {
        const int x = root(other[k].second), y = root(other[k - 1].second);
        if (x != y) parent[size_t(x)] = y, --count;
      }
    fans[v] = count;
  }
}

// Non-manifold vertices: incident faces must form a single fan. Returns them.
std::vector<int> check_vertex_fans(const MeshSoup& soup, const std::vector<char>& face_ok, MeshReport& r) {
  const size_t nv = size_t(r.vertices);
  std::vector<size_t> start(nv + 1, 0);
  for (size_t f = 0; f < soup.triangles.size(); ++f)
    if (face_ok[f])
      for (int v : soup.triangles[f]) ++start[size_t(v) + 1];
  for (size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  std::vector<int> vf(start[nv]);
  std::vector<size_t> fill(start.begin(), start.end() - 1);
  for (size_t f = 0; f < soup.triangles.size(); ++f)
    if (face_ok[f])
      for (int v : soup.triangles[f]) vf[fill[size_t(v)]++] = int(f);
  std::vector<int> fans(nv, 1), pinched;
  count_fans(soup, start, vf, 0, nv, fans);
  std::string nmv_example;
  for (size_t v = 0; v < nv; ++v)
    if (fans[v] > 1) {
      if (pinched.empty()) nmv_example = "vertex " + std::to_string(v) + " where " + std::to_string(fans[v]) + " fans of faces meet";
      pinched.push_back(int(v));
    }
  add(r, "non_manifold_vertices", "non-manifold vertices", long(pinched.size()), nmv_example, true,
      "split the vertex so that each fan of faces gets its own copy (e.g. 'split non-manifold vertices' in MeshLab)");
  return pinched;
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
  add(r, "degenerate_faces", "degenerate (zero-area) faces", degenerate, deg_example, false,
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
  add(r, "isolated_vertices", "isolated vertices (in no face)", isolated, iso_example, false,
      "they are ignored; delete loose vertices to silence this");
}

// Parts and genus: Euler characteristic per edge-connected component.
void find_parts(const MeshSoup& soup, const std::vector<char>& face_ok, const EdgeTable& t, MeshReport& r) {
  const long nv = r.vertices;
  UnionFind uf(soup.triangles.size());
  for (size_t e = 0; e < t.edges(); ++e)
    for (size_t i = t.group[e] + 1; i < t.group[e + 1]; ++i) uf.unite(t.face(t.group[e]), t.face(i));
  // Parts numbered in the order their first face comes (a table by root: a hash map of the roots
  // took a quarter of the 449k-vertex validation).
  std::vector<int> part_of_root(soup.triangles.size(), -1);
  r.face_part.assign(soup.triangles.size(), -1);
  r.parts = 0;
  for (size_t f = 0; f < soup.triangles.size(); ++f) {
    if (!face_ok[f]) continue;
    int& part = part_of_root[size_t(uf.find(int(f)))];
    if (part < 0) part = r.parts++;
    r.face_part[f] = part;
  }
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
  for (size_t e = 0; e < t.edges(); ++e) {
    const size_t i = t.group[e];
    pe[r.face_part[t.face(i)]]++;
    if (t.uses(e) != 1) continue;
    const int a = t.lo[i], b = t.hi[i];
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
    add(r, "parts", "connected parts", r.parts, "each part gets its own skeleton", false,
        "nothing to fix: several parts are supported");
}

// Signed volume of every part (faces with face_part -1 left out), each hole capped by a cone from
// the mean of its part's rim vertices (`rim`: the half-edges without an opposite, as (a, b, face))
// so that open parts have one too; measured from a vertex of the part (no cancellation far from
// (0, 0, 0)).
std::vector<double> part_volumes(const MeshSoup& soup, const std::vector<int>& face_part, int parts,
                                 const std::vector<std::array<int, 3>>& rim) {
  std::vector<double> volume(size_t(parts), 0.0);
  std::vector<int> origin(size_t(parts), -1);
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
  }
  std::vector<Eigen::Vector3d> apex(size_t(parts), Eigen::Vector3d::Zero());
  std::vector<long> count(size_t(parts), 0);
  for (const auto& [a, b, f] : rim)
    if (face_part[size_t(f)] >= 0) apex[size_t(face_part[size_t(f)])] += soup.points[size_t(a)], ++count[size_t(face_part[size_t(f)])];
  for (const auto& [a, b, f] : rim) {
    const int p = face_part[size_t(f)];
    if (p >= 0) tet(p, soup.points[size_t(b)], soup.points[size_t(a)], apex[size_t(p)] / double(count[size_t(p)]));
  }
  return volume;
}

// The --min-part that drops every part of diagonal up to `largest_flat` and keeps the part of
// diagonal `largest_solid`, as a round number (1, 2 or 5 times a power of ten) above
// largest_flat / whole; 0 when there is none below half of the solid part's share.
double speck_fraction(double largest_flat, double largest_solid, double whole) {
  if (!(whole > 0) || !(largest_flat > 0)) return 0;
  const double need = largest_flat / whole, keep = largest_solid / whole;
  for (double decade = std::pow(10.0, std::floor(std::log10(need))); decade < 1; decade *= 10)
    for (double m : {1.0, 2.0, 5.0})
      if (m * decade > need) return m * decade < 0.5 * keep ? m * decade : 0;
  return 0;
}

// A part whose signed volume is nought (its holes capped) is flat (both sides of one sheet, folded
// onto itself, or an open sheet): no capsule sees its surface from inside, and an encode of it is
// garbage with a success code (0 % of texels on their own surface). Relative to the
// part's own bounding box, so that it holds at any scale. Only for usable input.
void check_volumes(const MeshSoup& soup, const std::vector<char>& face_ok, const EdgeTable& t, MeshReport& r) {
  if (!r.usable() || r.parts == 0) return;
  std::vector<int> face_part = r.face_part;
  for (size_t f = 0; f < face_part.size(); ++f)
    if (!face_ok[f]) face_part[f] = -1;
  const std::vector<double> volume = part_volumes(soup, face_part, r.parts, boundary_halfedges(t));
  if (std::find(face_part.begin(), face_part.end(), -1) == face_part.end()) r.part_volume = volume;  // orient_outward's too
  std::vector<Eigen::Vector3d> lo(r.parts, Eigen::Vector3d::Constant(INFINITY)), hi(r.parts, Eigen::Vector3d::Constant(-INFINITY));
  for (size_t f = 0; f < soup.triangles.size(); ++f)
    if (face_part[f] >= 0)
      for (int v : soup.triangles[f]) lo[face_part[f]] = lo[face_part[f]].cwiseMin(soup.points[v]), hi[face_part[f]] = hi[face_part[f]].cwiseMax(soup.points[v]);
  long flat = 0;
  std::string example;
  double largest_flat = 0, largest_solid = 0;  // diagonals
  Eigen::Vector3d all_lo = Eigen::Vector3d::Constant(INFINITY), all_hi = Eigen::Vector3d::Constant(-INFINITY);
  for (int p = 0; p < r.parts; ++p) {
    const double d = (hi[p] - lo[p]).norm();
    const bool is_flat = std::abs(volume[p]) <= 1e-9 * d * d * d;
    double& largest = is_flat ? largest_flat : largest_solid;
    largest = std::max(largest, d);
    all_lo = all_lo.cwiseMin(lo[p]), all_hi = all_hi.cwiseMax(hi[p]);
    if (is_flat && !flat++)
      example = "part " + std::to_string(p) + " (" + std::to_string(r.faces_per_part[p]) + " faces) has volume " + number(volume[p]) +
                " within a box of diagonal " + number(d);
  }
  std::string fix = "give the part a thickness (e.g. 'solidify' in Blender); a surface mapped from a skeleton needs an inside";
  // The faces' box, as drop_small_soup_parts measures it (r's box also holds unused points).
  const double min_part = speck_fraction(largest_flat, largest_solid, (all_hi - all_lo).norm());
  if (flat) r.speck_min_part = min_part;
  if (flat && min_part > 0) fix += "; or, if it is a speck beside the model (a scan's stray triangle), drop it with --min-part " + number(min_part);
  add(r, "flat_parts", "parts enclosing no volume (flat: both sides of one sheet, or an open sheet)", flat, example, true, fix);
}

// An empty report with what the checks read from r (counts and bounding box).
MeshReport scratch_report(const MeshReport& r) {
  MeshReport s;
  s.vertices = r.vertices, s.faces = r.faces, s.bbox_min = r.bbox_min, s.bbox_max = r.bbox_max;
  return s;
}

void take_findings(MeshReport& r, MeshReport& from) {
  for (auto& f : from.findings) r.findings.push_back(std::move(f));
  from.findings.clear();
}

}  // namespace

bool TopologyScan::repair_needed() const {
  return !report.usable() || edges_not_closed_2_manifold || !nonmanifold_vertices.empty();
}

TopologyScan scan_topology(const MeshSoup& soup) {
  TopologyScan s;
  MeshReport& r = s.report;
  r.vertices = long(soup.points.size());
  r.faces = long(soup.triangles.size());
  if (soup.triangles.empty()) {
    add(r, "empty_mesh", "empty mesh (no faces)", 1, std::to_string(r.vertices) + " vertices but no face", true,
        "export the surface as triangles or polygons, not as points or lines");
    return s;
  }
  // The findings come in this order: fatal ones first, from coordinates to topology.
  s.bad_coordinates = check_coordinates(soup, r);
  s.face_ok = check_face_indices(soup, r);
  // The edges and the vertex fans on two threads, each into a report of its own; their findings
  // then join r in this order, so the report does not depend on the timing.
  MeshReport edges = scratch_report(r), fans = scratch_report(r);
  run_concurrently(
      [&] { s.nonmanifold_vertices = check_vertex_fans(soup, s.face_ok, fans); },
      [&] {
        s.table = edge_table(soup, s.face_ok);
        s.edges_not_closed_2_manifold = check_edges(s.table, soup.points.size(), edges);
      });
  s.findings_before_duplicates = r.findings.size();
  take_findings(r, edges);
  r.edges = edges.edges, r.boundary_loops = edges.boundary_loops;
  take_findings(r, fans);
  return s;
}

MeshReport finish_validation(const MeshSoup& soup, TopologyScan&& scan, EdgeTable* table_out) {
  MeshReport r = std::move(scan.report);
  if (table_out) *table_out = EdgeTable();
  if (soup.triangles.empty()) return r;
  const std::vector<char>& face_ok = scan.face_ok;
  // The checks that need no edge table on one thread while the parts are found on the other
  // (BENCHMARKS "Loading large meshes").
  MeshReport duplicated = scratch_report(r), degenerate = scratch_report(r), isolated = scratch_report(r), parts = scratch_report(r);
  run_concurrently(
      [&] {
        check_duplicated_faces(soup, face_ok, duplicated);
        check_degenerate_faces(soup, face_ok, scan.bad_coordinates, degenerate);
        check_isolated_vertices(soup, face_ok, isolated);
      },
      [&] { find_parts(soup, face_ok, scan.table, parts); });
  r.findings.insert(r.findings.begin() + long(scan.findings_before_duplicates), duplicated.findings.begin(), duplicated.findings.end());
  take_findings(r, degenerate);
  take_findings(r, isolated);
  take_findings(r, parts);
  r.parts = parts.parts, r.face_part = std::move(parts.face_part), r.genus_per_part = std::move(parts.genus_per_part);
  r.boundary_loops_per_part = std::move(parts.boundary_loops_per_part), r.faces_per_part = std::move(parts.faces_per_part);
  check_volumes(soup, face_ok, scan.table, r);
  if (soup.polygons_triangulated)
    add(r, "polygons_triangulated", "polygons triangulated on read (ear clipping)", soup.polygons_triangulated,
        "faces with more than three corners", false,
        "nothing to fix; triangulate in the modelling tool for control over the diagonals");
  if (table_out && std::find(face_ok.begin(), face_ok.end(), char(0)) == face_ok.end()) *table_out = std::move(scan.table);
  return r;
}

MeshReport validate_mesh(const MeshSoup& soup, EdgeTable* table_out) {
  return finish_validation(soup, scan_topology(soup), table_out);
}

long orient_outward(MeshSoup& soup, MeshReport& report) {
  std::vector<double> volume = report.part_volume;  // measured by validation when every face is in a part
  if (volume.size() != size_t(report.parts)) {
    std::vector<std::array<int, 3>> rim;
    if (report.boundary_loops > 0) {
      std::vector<char> in_part(soup.triangles.size(), 0);
      for (size_t f = 0; f < in_part.size(); ++f) in_part[f] = report.face_part[f] >= 0;
      rim = boundary_halfedges(edge_table(soup, in_part));
    }
    volume = part_volumes(soup, report.face_part, report.parts, rim);
  }
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
    report.findings.push_back({"faces_flipped", "faces flipped to point outwards", flipped,
                               "part " + std::to_string(example) + " was inside out", false,
                               "nothing to fix; the input's normals pointed inwards"});
  for (double& v : report.part_volume) v = std::abs(v);
  return flipped;
}

}  // namespace sdm
