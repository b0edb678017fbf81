#include "libstm/mesh/add_faces.h"

#include "libstm/mesh/edge_table.h"

#include <utility>

namespace sdm {

namespace {

// Per face side 3 f + c, the side of another face running the other way along the same edge, or
// -1 on a boundary. False when an edge has more than two sides or two in the same direction.
bool opposite_sides(const EdgeTable& t, size_t faces, std::vector<int>& opposite) {
  if (t.halfedge.size() != 3 * faces) return false;
  opposite.assign(3 * faces, -1);
  for (size_t e = 0; e < t.edges(); ++e) {
    const size_t i = t.group[e];
    if (t.uses(e) == 1) continue;
    if (t.uses(e) > 2 || t.forward[i] == t.forward[i + 1]) return false;
    opposite[size_t(t.halfedge[i])] = t.halfedge[i + 1];
    opposite[size_t(t.halfedge[i + 1])] = t.halfedge[i];
  }
  return true;
}

// The halfedge structure add_face builds, on flat arrays: halfedges 2e and 2e + 1 are edge e's,
// the first running from edge[e][0] to edge[e][1]; -1 stands for an invalid handle.
struct Links {
  struct Halfedge {
    int next = -1, prev = -1, face = -1;
  };
  std::vector<std::array<int, 2>> edge;  // per edge: from, to of its first halfedge
  std::vector<Halfedge> he;              // per halfedge
  std::vector<int> vertex_out;           // per vertex: its outgoing halfedge
  std::vector<int> open_out;             // per vertex: its outgoing halfedges without a face
  std::vector<int> face_first;           // per face: its halfedge
  std::vector<int> side;                 // per face side 3 f + c: its halfedge
  std::vector<std::pair<int, int>> next_cache;

  Links(size_t vertices, size_t faces) : vertex_out(vertices, -1), open_out(vertices, 0), face_first(faces, -1), side(3 * faces, -1) {
    edge.reserve(faces * 3 / 2 + 3), he.reserve(3 * faces + 6);
  }
  int next(int h) const { return he[size_t(h)].next; }
  int prev(int h) const { return he[size_t(h)].prev; }
  int face(int h) const { return he[size_t(h)].face; }
  bool is_boundary_vertex(int v) const { return vertex_out[size_t(v)] < 0 || face(vertex_out[size_t(v)]) < 0; }
  int new_edge(int a, int b) {
    const int h = int(he.size());
    edge.push_back({a, b});
    he.resize(he.size() + 2);
    return h;
  }
  void set_next(int h, int n) { he[size_t(h)].next = n, he[size_t(n)].prev = h; }
  // The outgoing halfedges of v clockwise from its current one (OpenMesh's vertex circulator):
  // the first on a boundary becomes v's outgoing halfedge.
  void adjust_outgoing(int v) {
    if (open_out[size_t(v)] == 0) return;  // the circulation would find none
    const int start = vertex_out[size_t(v)];
    int h = start;
    for (size_t steps = 0; h >= 0 && steps <= he.size(); ++steps) {
      if (face(h) < 0) {
        vertex_out[size_t(v)] = h;
        return;
      }
      h = next(h ^ 1);
      if (h == start) return;
    }
  }
  bool relink_patch(int inner_prev, int inner_next);
  bool add_face(int f, const std::array<int, 3>& v, const std::vector<int>& opposite);
};

// A face joins two existing sides at a vertex whose boundary does not run from one to the other:
// the fan between them moves into another gap of the vertex (add_face's patch relinking).
bool Links::relink_patch(int inner_prev, int inner_next) {
  int boundary_prev = inner_next ^ 1;
  size_t steps = 0;
  do {
    boundary_prev = next(boundary_prev) ^ 1;
    if (boundary_prev < 0 || ++steps > he.size()) return false;
  } while (face(boundary_prev) >= 0);
  if (boundary_prev == inner_prev) return false;
  const int boundary_next = next(boundary_prev);
  next_cache.emplace_back(boundary_prev, next(inner_prev));
  next_cache.emplace_back(prev(inner_next), boundary_next);
  next_cache.emplace_back(inner_prev, inner_next);
  return true;
}

// add_face(v0, v1, v2) as face f: its sides found or created, the links about its corners set
// as add_face sets them (through its cache of next links, applied at the end), then the
// outgoing halfedges adjusted at the corners whose outgoing halfedge the face took.
bool Links::add_face(int f, const std::array<int, 3>& v, const std::vector<int>& opposite) {
  std::array<int, 3> h{};
  std::array<bool, 3> fresh{}, adjust{};
  for (size_t i = 0; i < 3; ++i) {
    if (!is_boundary_vertex(v[i])) return false;
    // The side's halfedge exists when the opposite side's face came earlier: its twin.
    const int o = opposite[3 * size_t(f) + i];
    fresh[i] = o < 0 || o / 3 > f;
    if (!fresh[i]) {
      h[i] = side[size_t(o)] ^ 1;
      if (face(h[i]) >= 0) return false;
    }
  }
  next_cache.clear();
  for (size_t i = 0, ii = 1; i < 3; ++i, ii = (ii + 1) % 3)
    if (!fresh[i] && !fresh[ii] && next(h[i]) != h[ii] && !relink_patch(h[i], h[ii])) return false;
  for (size_t i = 0, ii = 1; i < 3; ++i, ii = (ii + 1) % 3) {
    if (fresh[i]) {
      h[i] = new_edge(v[i], v[ii]);
      ++open_out[size_t(v[ii])];  // the new edge's other halfedge, until a face takes it
    } else {
      --open_out[size_t(v[i])];
    }
  }
  face_first[size_t(f)] = h[2];
  for (size_t i = 0, ii = 1; i < 3; ++i, ii = (ii + 1) % 3) {
    const int vh = v[ii], inner_prev = h[i], inner_next = h[ii];
    const int outer_prev = inner_next ^ 1, outer_next = inner_prev ^ 1;
    int& out = vertex_out[size_t(vh)];
    if (fresh[i] && !fresh[ii]) {
      next_cache.emplace_back(prev(inner_next), outer_next);
      out = outer_next;
    } else if (!fresh[i] && fresh[ii]) {
      next_cache.emplace_back(outer_prev, next(inner_prev));
      out = next(inner_prev);
    } else if (fresh[i] && fresh[ii]) {
      if (out < 0) {
        out = outer_next;
        next_cache.emplace_back(outer_prev, outer_next);
      } else {
        next_cache.emplace_back(prev(out), outer_next);
        next_cache.emplace_back(outer_prev, out);
      }
    } else {
      adjust[ii] = out == inner_next;
    }
    if (fresh[i] || fresh[ii]) next_cache.emplace_back(inner_prev, inner_next);
    he[size_t(h[i])].face = f;
  }
  for (const auto& [h, n] : next_cache) set_next(h, n);
  for (size_t i = 0; i < 3; ++i) {
    side[3 * size_t(f) + i] = h[i];
    if (adjust[i]) adjust_outgoing(v[i]);
  }
  return true;
}

// OpenMesh's arrays filled from the links: edges and faces created in their order, then every
// link set (set_next_halfedge_handle sets prev too).
void fill_mesh(Mesh& mesh, const Links& l) {
  using VH = Mesh::VertexHandle;
  using HH = Mesh::HalfedgeHandle;
  using FH = Mesh::FaceHandle;
  // One resize of every array and property instead of new_edge's and new_face's one element at a
  // time (each resizes every property): the same arrays; the 449k-vertex build 0.24-0.26 -> 0.20-0.22 s.
  mesh.resize(mesh.n_vertices(), l.edge.size(), l.face_first.size());
  for (size_t e = 0; e < l.edge.size(); ++e) {
    mesh.set_vertex_handle(HH(int(2 * e)), VH(l.edge[e][1]));
    mesh.set_vertex_handle(HH(int(2 * e + 1)), VH(l.edge[e][0]));
  }
  for (size_t f = 0; f < l.face_first.size(); ++f) mesh.set_halfedge_handle(FH(int(f)), HH(l.face_first[f]));
  for (size_t h = 0; h < l.he.size(); ++h) {
    if (l.he[h].next >= 0) mesh.set_next_halfedge_handle(HH(int(h)), HH(l.he[h].next));
    if (l.he[h].face >= 0) mesh.set_face_handle(HH(int(h)), FH(l.he[h].face));
  }
  for (size_t v = 0; v < l.vertex_out.size(); ++v)
    if (l.vertex_out[v] >= 0) mesh.set_halfedge_handle(VH(int(v)), HH(l.vertex_out[v]));
}

}  // namespace

bool add_faces(Mesh& mesh, const std::vector<std::array<int, 3>>& triangles, const EdgeTable* table) {
  if (mesh.n_edges() != 0 || mesh.n_faces() != 0) return false;
  const size_t nv = mesh.n_vertices();
  for (const auto& t : triangles)
    for (size_t c = 0; c < 3; ++c)
      if (t[c] < 0 || size_t(t[c]) >= nv || t[c] == t[(c + 1) % 3]) return false;
  std::vector<int> opposite;
  if (!opposite_sides(table ? *table : edge_table(triangles, nv), triangles.size(), opposite)) return false;
  Links links(nv, triangles.size());
  for (size_t f = 0; f < triangles.size(); ++f)
    if (!links.add_face(int(f), triangles[f], opposite)) return false;
  fill_mesh(mesh, links);
  return true;
}

size_t add_faces_or_each(Mesh& mesh, const std::vector<std::array<int, 3>>& triangles) {
  if (add_faces(mesh, triangles)) return 0;
  size_t refused = 0;
  for (const auto& t : triangles)
    refused += !mesh.add_face(Mesh::VertexHandle(t[0]), Mesh::VertexHandle(t[1]), Mesh::VertexHandle(t[2])).is_valid();
  return refused;
}

}  // namespace sdm
