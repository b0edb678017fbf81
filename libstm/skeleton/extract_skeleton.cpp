#include "libstm/skeleton/extract_skeleton.h"

#include "libstm/mesh/inside_mesh.h"
#include "libstm/mesh/isotropic_remesh.h"
#include "libstm/skeleton/medial_poles.h"
#include "libstm/geometry/triangle_bvh.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cmath>
#include <exception>
#include <future>
#include <map>
#include <mutex>
#include <numeric>
#include <optional>
#include <set>
#include <thread>

namespace sdm {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

void insert_sorted(std::vector<int>& v, int x) {
  auto it = std::lower_bound(v.begin(), v.end(), x);
  if (it == v.end() || *it != x) v.insert(it, x);
}
void erase_sorted(std::vector<int>& v, int x) {
  auto it = std::lower_bound(v.begin(), v.end(), x);
  if (it != v.end() && *it == x) v.erase(it);
}

// The result of surgery for one part: graph on surviving vertices and the cluster of each.
struct Graph {
  std::vector<Eigen::Vector3d> pos;       // node position
  std::vector<Eigen::Vector3d> fallback;  // contracted position, used when pos must be pulled in
  std::vector<std::vector<int>> verts;    // original (part-local) vertices per node
  std::set<std::pair<int, int>> edges;
};

// Connectivity surgery: edge collapse of the contracted mesh as a simplicial complex until no
// face is left.
Graph surgery(const Eigen::MatrixX3d& O, const Eigen::MatrixX3d& P, const Eigen::MatrixX3i& F, const InsideMesh& in,
              int genus, const SkeletonOptions& opt, SkeletonStats& st) {
  const int n = int(P.rows()), m = int(F.rows());
  std::vector<std::vector<int>> nbr(n), vfaces(n);
  std::vector<std::array<int, 3>> faces(m);
  std::vector<char> face_alive(m, 1), alive(n, 1);
  for (int f = 0; f < m; ++f) {
    for (int k = 0; k < 3; ++k) {
      faces[f][k] = F(f, k);
      vfaces[F(f, k)].push_back(f);
      nbr[F(f, k)].push_back(F(f, (k + 1) % 3));
      nbr[F(f, (k + 1) % 3)].push_back(F(f, k));
    }
  }
  for (auto& v : nbr) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
  }
  int faces_left = m;
  std::vector<Eigen::Matrix4d> Q(n, Eigen::Matrix4d::Zero());
  for (int i = 0; i < n; ++i)
    for (int k : nbr[i]) {
      Eigen::Vector3d a = P.row(k) - P.row(i);
      const double len = a.norm();
      if (!(len > 0)) continue;
      a /= len;
      Eigen::Matrix<double, 3, 4> K;
      K << 0, -a.z(), a.y(), 0, a.z(), 0, -a.x(), 0, -a.y(), a.x(), 0, 0;
      K.col(3) = -a.cross(Eigen::Vector3d(P.row(i)));
      Q[i] += K.transpose() * K;
    }
  std::vector<Eigen::Vector3d> csum(n);
  std::vector<int> ccount(n, 1), parent(n);
  for (int i = 0; i < n; ++i) csum[i] = O.row(i), parent[i] = i;
  auto centroid = [&](int i) { return Eigen::Vector3d(csum[i] / ccount[i]); };

  auto has_face = [&](int i, int j) {
    for (int f : vfaces[i])
      if (faces[f][0] == j || faces[f][1] == j || faces[f][2] == j) return true;
    return false;
  };
  auto has_triangle = [&](int i, int j, int k) {
    for (int f : vfaces[i]) {
      const auto& t = faces[f];
      const bool hj = t[0] == j || t[1] == j || t[2] == j, hk = t[0] == k || t[1] == k || t[2] == k;
      if (hj && hk) return true;
    }
    return false;
  };
  // Sum of the edge lengths around each vertex (Au et al.'s sampling cost), kept up to date by
  // the collapses: positions never move, so only vertices whose neighbours changed need it anew.
  std::vector<double> ring_length(n, 0.0);
  auto update_ring = [&](int i) {
    double ring = 0;
    for (int k : nbr[i]) ring += (P.row(i) - P.row(k)).norm();
    ring_length[i] = ring;
  };
  for (int i = 0; i < n; ++i) update_ring(i);
  auto cost = [&](int i, int j) {
    const Eigen::Vector4d pj(P(j, 0), P(j, 1), P(j, 2), 1.0);
    const double shape = pj.dot((Q[i] + Q[j]) * pj);
    const double sampling = (P.row(i) - P.row(j)).norm() * ring_length[i];
    return opt.shape_weight * shape + opt.sampling_weight * sampling;
  };
  // Collapsing i into j kills the loop i-j-k of every common neighbour k without a triangle ijk.
  // Allowed only when the loop bounds a disk inside the volume (a cross-section of a tube), not
  // when it goes around a handle: tested on the triangle of the cluster centroids, shrunk a
  // little because single-vertex clusters lie on the surface.
  auto keeps_cycles = [&](int i, int j) {
    std::vector<int> common;
    std::set_intersection(nbr[i].begin(), nbr[i].end(), nbr[j].begin(), nbr[j].end(), std::back_inserter(common));
    for (int k : common) {
      if (has_triangle(i, j, k)) continue;
      const Eigen::Vector3d a = centroid(i), b = centroid(j), c = centroid(k);
      const Eigen::Vector3d g = (a + b + c) / 3.0;
      if (in.triangle_crosses(g + 0.9 * (a - g), g + 0.9 * (b - g), g + 0.9 * (c - g))) return false;
    }
    return true;
  };

  struct Entry {
    double cost;
    int i, j;
    unsigned si, sj;
    bool operator>(const Entry& o) const {
      if (cost != o.cost) return cost > o.cost;
      if (i != o.i) return i > o.i;
      return j > o.j;
    }
  };
  std::vector<unsigned> stamp(n, 0);
  // A heap with lazy deletion: a collapse invalidates the entries of the vertices it
  // touches (stamps) and queues them anew. Most entries go stale before they reach the top, and
  // popping one costs a sift through the whole heap, while a sweep costs a few comparisons per
  // entry: stale entries are swept out as soon as they make up half of the heap (the heap
  // operations are most of the surgery's time; sweeping at three quarters took 25-40 % longer).
  // Four-ary: a pop sifts through half the levels of a binary heap, and pops (mostly of stale
  // entries) dominate. Any priority queue pops the live entries in the same order: their keys
  // (cost, i, j) are distinct.
  std::vector<Entry> heap;
  const std::greater<Entry> later;
  auto sift_down = [&](size_t at) {
    const size_t size = heap.size();
    const Entry e = heap[at];
    for (;;) {
      const size_t first = 4 * at + 1;
      if (first >= size) break;
      size_t best = first;
      for (size_t c = first + 1; c < std::min(first + 4, size); ++c)
        if (later(heap[best], heap[c])) best = c;
      if (!later(e, heap[best])) break;
      heap[at] = heap[best];
      at = best;
    }
    heap[at] = e;
  };
  auto heap_push = [&](const Entry& e) {
    size_t at = heap.size();
    heap.push_back(e);
    while (at > 0) {
      const size_t up = (at - 1) / 4;
      if (!later(heap[up], e)) break;
      heap[at] = heap[up];
      at = up;
    }
    heap[at] = e;
  };
  auto heap_pop = [&] {
    const Entry top = heap.front();
    heap.front() = heap.back();
    heap.pop_back();
    if (!heap.empty()) sift_down(0);
    return top;
  };
  size_t sweep_at = size_t(n) + 64;
  auto stale = [&](const Entry& e) { return !alive[e.i] || !alive[e.j] || e.si != stamp[e.i] || e.sj != stamp[e.j]; };
  auto queue = [&](int i, int j) {
    heap_push({cost(i, j), i, j, stamp[i], stamp[j]});
  };
  auto push = [&](int i, int j) {
    if (has_face(i, j)) queue(i, j);
  };
  // The vertices sharing a face with k, marked once, so that queueing all of k's edges does not
  // scan k's faces for every one of them.
  std::vector<unsigned> face_mark(n, 0);
  unsigned face_marks = 0;
  auto mark_face_neighbours = [&](int k) {
    ++face_marks;
    for (int f : vfaces[k])
      for (int x : faces[f]) face_mark[x] = face_marks;
  };
  for (int i = 0; i < n; ++i)
    for (int j : nbr[i]) push(i, j);

  auto collapse = [&](int i, int j) {
    for (int f : std::vector<int>(vfaces[i])) {
      auto& t = faces[f];
      const bool hj = t[0] == j || t[1] == j || t[2] == j;
      bool kill = hj;
      if (!hj) {
        for (int& x : t)
          if (x == i) x = j;
        for (int g : vfaces[j]) {
          const auto& u = faces[g];
          if (std::is_permutation(u.begin(), u.end(), t.begin())) kill = true;
        }
      }
      if (kill) {
        face_alive[f] = 0;
        --faces_left;
        for (int x : t) {
          auto& vf = vfaces[x == i ? i : x];
          vf.erase(std::remove(vf.begin(), vf.end(), f), vf.end());
        }
        auto& vi = vfaces[i];
        vi.erase(std::remove(vi.begin(), vi.end(), f), vi.end());
      } else {
        vfaces[j].push_back(f);
      }
    }
    vfaces[i].clear();
    const std::vector<int> old_nbr = std::move(nbr[i]);
    for (int k : old_nbr) {
      erase_sorted(nbr[k], i);
      if (k == j) continue;
      insert_sorted(nbr[k], j);
      insert_sorted(nbr[j], k);
    }
    nbr[i].clear();
    Q[j] += Q[i];
    csum[j] += csum[i];
    ccount[j] += ccount[i];
    parent[i] = j;
    alive[i] = 0;
    update_ring(j);
    for (int k : old_nbr)
      if (k != j) update_ring(k);
    ++stamp[j];
    for (int k : nbr[j]) ++stamp[k];
    for (int k : nbr[j]) {
      push(j, k);
      mark_face_neighbours(k);
      if (face_mark[j] == face_marks) queue(k, j);
      for (int l : nbr[k])
        if (l != j && face_mark[l] == face_marks) queue(k, l);
    }
  };

  while (faces_left > 0) {
    if (heap.size() > sweep_at) {
      heap.erase(std::remove_if(heap.begin(), heap.end(), stale), heap.end());
      for (size_t at = heap.size() / 4 + 1; at-- > 0;)
        if (at < heap.size()) sift_down(at);
      sweep_at = std::max(size_t(n) + 64, 2 * heap.size());
    }
    if (heap.empty()) {
      // Every remaining collapse would break a cycle: take the cheapest anyway.
      double best = std::numeric_limits<double>::infinity();
      int bi = -1, bj = -1;
      for (int f = 0; f < m; ++f) {
        if (!face_alive[f]) continue;
        for (int k = 0; k < 3; ++k)
          for (int s = 0; s < 2; ++s) {
            const int i = faces[f][(k + s) % 3], j = faces[f][(k + 1 - s + 3) % 3];
            const double c = cost(i, j);
            if (c < best || (c == best && std::make_pair(i, j) < std::make_pair(bi, bj))) best = c, bi = i, bj = j;
          }
      }
      if (bi < 0) break;
      ++st.forced_collapses;
      collapse(bi, bj);
      continue;
    }
    const Entry e = heap_pop();
    if (stale(e)) continue;
    if (!has_face(e.i, e.j)) continue;
    // A part of genus 0 has no handle for a loop to go around: every loop bounds a disk.
    if (genus > 0 && !keeps_cycles(e.i, e.j)) {
      ++st.refused_collapses;
      continue;
    }
    collapse(e.i, e.j);
  }

  Graph g;
  std::vector<int> node_of(n, -1);
  for (int i = 0; i < n; ++i)
    if (alive[i]) {
      node_of[i] = int(g.pos.size());
      g.pos.push_back(centroid(i));
      g.fallback.push_back(P.row(i));
      g.verts.emplace_back();
    }
  for (int v = 0; v < n; ++v) {
    int r = v;
    while (parent[r] != r) r = parent[r];
    g.verts[node_of[r]].push_back(v);
  }
  for (int i = 0; i < n; ++i)
    if (alive[i])
      for (int k : nbr[i])
        if (i < k) g.edges.insert({node_of[i], node_of[k]});
  return g;
}

// Refinement on the graph: short end branches and short edges merged, positions kept inside.
void refine(Graph& g, const Eigen::MatrixX3d& O, const InsideMesh& in, const TriangleBvh& surface, double diag,
            const SkeletonOptions& opt) {
  const int n = int(g.pos.size());
  std::vector<char> alive(n, 1);
  std::vector<std::vector<int>> adj(n);
  for (const auto& e : g.edges) adj[e.first].push_back(e.second), adj[e.second].push_back(e.first);
  for (auto& a : adj) std::sort(a.begin(), a.end());
  auto com = [&](const std::vector<int>& vs) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int v : vs) c += O.row(v).transpose();
    return Eigen::Vector3d(c / double(vs.size()));
  };
  auto radius = [&](int a) {
    double r = 0;
    for (int v : g.verts[a]) r += (O.row(v).transpose() - g.pos[a]).norm();
    return r / g.verts[a].size();
  };
  auto node_ok = [&](int a, const Eigen::Vector3d& p, int skip) {
    if (!in.inside(p)) return false;
    for (int b : adj[a])
      if (b != skip && in.segment_crosses(p, g.pos[b])) return false;
    return true;
  };
  // Merges b into a; returns false (and changes nothing) when a's new position and edges cannot
  // be kept inside or when a cycle would lose a segment below three.
  auto merge = [&](int a, int b, bool force) {
    std::vector<int> common;
    std::set_intersection(adj[a].begin(), adj[a].end(), adj[b].begin(), adj[b].end(), std::back_inserter(common));
    if (!common.empty()) return false;
    std::vector<int> vs = g.verts[a];
    vs.insert(vs.end(), g.verts[b].begin(), g.verts[b].end());
    std::vector<int> nb;
    for (int x : adj[a])
      if (x != b) nb.push_back(x);
    for (int x : adj[b])
      if (x != a) nb.push_back(x);
    Eigen::Vector3d p = com(vs);
    auto ok = [&](const Eigen::Vector3d& q) {
      if (!in.inside(q)) return false;
      for (int x : nb)
        if (in.segment_crosses(q, g.pos[x])) return false;
      return true;
    };
    if (!ok(p)) {
      const Eigen::Vector3d alt[2] = {g.pos[a], g.pos[b]};
      bool found = false;
      for (const auto& q : alt)
        if (ok(q)) {
          p = q, found = true;
          break;
        }
      if (!found && !force) return false;
      if (!found) p = g.pos[a];
    }
    g.verts[a] = std::move(vs);
    g.verts[b].clear();
    g.pos[a] = p;
    alive[b] = 0;
    for (int x : adj[b]) {
      erase_sorted(adj[x], b);
      if (x != a) insert_sorted(adj[x], a), insert_sorted(adj[a], x);
    }
    adj[b].clear();
    erase_sorted(adj[a], b);
    return true;
  };

  // Positions: centre of the original vertices; when that leaves the volume (or lies on the
  // surface, as the centre of a flat cap does) or an edge crosses the surface, pulled back toward
  // the contracted position, then nudged along the node's edges into the volume.
  auto place = [&](int a) {
    if (node_ok(a, g.pos[a], -1)) return;
    const Eigen::Vector3d target = g.pos[a], back = g.fallback[a];
    for (double t = 0.75; t > 0.01; t -= 0.25) {
      const Eigen::Vector3d q = back + t * (target - back);
      if (node_ok(a, q, -1)) {
        g.pos[a] = q;
        return;
      }
    }
    if (node_ok(a, back, -1)) {
      g.pos[a] = back;
      return;
    }
    for (double t : {0.02, 0.05, 0.1, 0.2, 0.35, 0.5})
      for (int b : adj[a]) {
        const Eigen::Vector3d q = target + t * (g.pos[b] - target);
        if (node_ok(a, q, -1)) {
          g.pos[a] = q;
          return;
        }
      }
  };
  const double min_branch = opt.min_branch * diag;
  double max_radius = 0;
  for (int a = 0; a < n; ++a) max_radius = std::max(max_radius, radius(a));

  for (bool changed = true; changed;) {
    changed = false;
    // End branches shorter than min_branch: merged into the junction they hang from.
    for (int a = 0; a < n; ++a) {
      if (!alive[a] || adj[a].size() != 1) continue;
      std::vector<int> chain = {a};
      double len = 0;
      int prev = a, cur = adj[a][0];
      len += (g.pos[a] - g.pos[cur]).norm();
      const double limit = std::max(min_branch, opt.prune_radius * max_radius);  // walk no further
      while (adj[cur].size() == 2 && len < limit) {
        const int next = adj[cur][0] == prev ? adj[cur][1] : adj[cur][0];
        chain.push_back(cur);
        len += (g.pos[cur] - g.pos[next]).norm();
        prev = cur, cur = next;
      }
      // A branch that does not reach out of its junction's inscribed ball is a bump, not a limb.
      if (adj[cur].size() >= 3 &&
          (len < min_branch || len < opt.prune_radius * surface.closest_point(g.pos[cur]).distance)) {
        for (auto it = chain.rbegin(); it != chain.rend(); ++it) merge(cur, *it, true);
        changed = true;
      }
    }
    // Short edges: shorter than the local radius (or than min_branch), shortest relative first.
    std::vector<std::tuple<double, int, int>> cand;
    for (int a = 0; a < n; ++a) {
      if (!alive[a]) continue;
      const double ra = radius(a);
      for (int b : adj[a]) {
        if (b < a) continue;
        const double len = (g.pos[a] - g.pos[b]).norm();
        const double lim = std::max(opt.segment_radius * std::min(ra, radius(b)), min_branch);
        if (len < lim) cand.emplace_back(len / lim, a, b);
      }
    }
    std::sort(cand.begin(), cand.end());
    std::vector<char> touched(n, 0);
    for (const auto& [r, a, b] : cand) {
      if (touched[a] || touched[b] || !alive[a] || !alive[b]) continue;
      // Keep the node with more vertices, so ends and junctions stay where the mass is.
      const bool keep_a = g.verts[a].size() >= g.verts[b].size();
      if (merge(keep_a ? a : b, keep_a ? b : a, true)) touched[a] = touched[b] = 1, changed = true;
    }
  }

  for (int a = 0; a < n; ++a)
    if (alive[a]) place(a);

  Graph out;
  std::vector<int> id(n, -1);
  for (int a = 0; a < n; ++a)
    if (alive[a]) {
      id[a] = int(out.pos.size());
      out.pos.push_back(g.pos[a]);
      out.fallback.push_back(g.fallback[a]);
      out.verts.push_back(std::move(g.verts[a]));
    }
  for (int a = 0; a < n; ++a)
    if (alive[a])
      for (int b : adj[a])
        if (a < b) out.edges.insert({id[a], id[b]});
  g = std::move(out);
}


// The contraction proxy: the part remeshed isotropically to about proxy_max_vertices vertices,
// its vertices projected onto the part's surface. An equilateral mesh of area A and edge length l has about
// 2 A / (sqrt(3) l^2) vertices.
void make_proxy(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const SkeletonOptions& opt, Eigen::MatrixX3d& XV,
                Eigen::MatrixX3i& XF) {
  double area = 0;
  for (int f = 0; f < F.rows(); ++f)
    area += 0.5 * (V.row(F(f, 1)) - V.row(F(f, 0))).cross(V.row(F(f, 2)) - V.row(F(f, 0))).norm();
  const int target = std::max(opt.proxy_max_vertices, 4);
  const double len = std::sqrt(2.0 * area / (std::sqrt(3.0) * target));
  Mesh m;
  std::vector<Mesh::VertexHandle> h(V.rows());
  for (int i = 0; i < V.rows(); ++i) h[i] = m.add_vertex({V(i, 0), V(i, 1), V(i, 2)});
  for (int f = 0; f < F.rows(); ++f) m.add_face(h[F(f, 0)], h[F(f, 1)], h[F(f, 2)]);
  const TriangleBvh bvh(V, F);
  isotropic_remesh(m, len, 8, [&](const Eigen::Vector3d& p) { return bvh.closest_point(p).point; });
  XV = vertex_matrix(m);
  XF = face_matrix(m);
}

// Every vertex of the part goes to the node of the nearest corner of its closest proxy face,
// unless that face looks the other way (the far side of a thin sheet): then to the nearest proxy
// vertex whose normal agrees. A node that receives no vertex takes the nearest vertex of a node
// that owns several, so every node owns at least one.
std::vector<int> map_to_nodes(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::MatrixX3d& XV,
                              const Eigen::MatrixX3i& XF, const Graph& g) {
  auto normals = [](const Eigen::MatrixX3d& P, const Eigen::MatrixX3i& T, Eigen::MatrixX3d& fn) {
    Eigen::MatrixX3d vn = Eigen::MatrixX3d::Zero(P.rows(), 3);
    fn.resize(T.rows(), 3);
    for (int f = 0; f < T.rows(); ++f) {
      const Eigen::Vector3d n = (P.row(T(f, 1)) - P.row(T(f, 0))).cross(P.row(T(f, 2)) - P.row(T(f, 0)));
      fn.row(f) = n.normalized();
      for (int k = 0; k < 3; ++k) vn.row(T(f, k)) += n;
    }
    vn.rowwise().normalize();
    return vn;
  };
  Eigen::MatrixX3d fn, xfn;
  const Eigen::MatrixX3d vn = normals(V, F, fn), xvn = normals(XV, XF, xfn);
  std::vector<int> xnode(XV.rows(), -1);
  for (size_t a = 0; a < g.verts.size(); ++a)
    for (int v : g.verts[a]) xnode[v] = int(a);
  const TriangleBvh bvh(XV, XF);
  std::vector<int> owner(V.rows());
  for (int i = 0; i < V.rows(); ++i) {
    const Eigen::Vector3d p = V.row(i), n = vn.row(i);
    const auto c = bvh.closest_point(p);
    int best = -1;
    if (Eigen::Vector3d(xfn.row(c.face)).dot(n) > 0) {
      double d = INFINITY;
      for (int k = 0; k < 3; ++k) {
        const double e = (XV.row(XF(c.face, k)).transpose() - c.point).squaredNorm();
        if (e < d) d = e, best = XF(c.face, k);
      }
    } else {
      double d = INFINITY;
      for (int x = 0; x < XV.rows(); ++x) {
        const double e = (XV.row(x).transpose() - p).squaredNorm();
        if (Eigen::Vector3d(xvn.row(x)).dot(n) > 0 && e < d) d = e, best = x;
      }
      if (best < 0) best = XF(c.face, 0);
    }
    owner[i] = xnode[best];
  }
  std::vector<int> count(g.pos.size(), 0);
  for (int o : owner) ++count[o];
  for (size_t a = 0; a < g.pos.size(); ++a) {
    if (count[a] > 0) continue;
    int best = -1;
    double d = INFINITY;
    for (int i = 0; i < V.rows(); ++i) {
      const double e = (V.row(i).transpose() - g.pos[a]).squaredNorm();
      if (count[owner[i]] > 1 && e < d) d = e, best = i;
    }
    if (best < 0) continue;
    --count[owner[best]];
    owner[best] = int(a);
    ++count[a];
  }
  return owner;
}

// An edge that still crosses the surface after refinement (a spur cutting a corner of a thin
// wall) is bent through a new node: the medial pole, among those of all vertices, that sees both
// ends from inside with the shortest detour. The vertex of that pole moves to the new node.
void bend_crossing_edges(Graph& g, const InsideMesh& in, const Eigen::MatrixX3d& poles) {
  const std::vector<std::pair<int, int>> edges(g.edges.begin(), g.edges.end());
  std::vector<std::pair<int, int>> dead_ends;
  for (const auto& [a, b] : edges) {
    if (in.segment_inside(g.pos[a], g.pos[b])) continue;
    double best = INFINITY;
    int bv = -1, from = -1;
    for (int owner = 0; owner < int(g.verts.size()); ++owner) {
      if (g.verts[owner].size() < 2) continue;
      for (int v : g.verts[owner]) {
        const Eigen::Vector3d p = poles.row(v);
        const double len = (p - g.pos[a]).norm() + (p - g.pos[b]).norm();
        if (len >= best || !in.segment_inside(g.pos[a], p) || !in.segment_inside(p, g.pos[b])) continue;
        best = len, bv = v, from = owner;
      }
    }
    if (bv < 0) {
      dead_ends.push_back({a, b});
      continue;
    }
    const int c = int(g.pos.size());
    g.pos.push_back(poles.row(bv));
    g.fallback.push_back(poles.row(bv));
    auto& vs = g.verts[from];
    vs.erase(std::find(vs.begin(), vs.end(), bv));
    g.verts.push_back({bv});
    g.edges.erase({a, b});
    g.edges.insert({std::min(a, c), std::max(a, c)});
    g.edges.insert({std::min(b, c), std::max(b, c)});
  }
  // No detour: when the edge leads to an end branch, the branch goes into the node on the other
  // side (a limb that cannot be reached from inside is not one the layout could use).
  std::vector<char> gone(g.pos.size(), 0);
  for (const auto& [a, b] : dead_ends) {
    std::vector<std::vector<int>> adj(g.pos.size());
    for (const auto& e : g.edges) adj[e.first].push_back(e.second), adj[e.second].push_back(e.first);
    for (const auto& [keep, start] : {std::make_pair(a, b), std::make_pair(b, a)}) {
      std::vector<int> chain = {start};
      int prev = keep, cur = start;
      while (adj[cur].size() == 2) {
        const int next = adj[cur][0] == prev ? adj[cur][1] : adj[cur][0];
        prev = cur, cur = next;
        if (cur == keep) break;
        chain.push_back(cur);
      }
      if (adj[cur].size() != 1 || cur == keep) continue;
      for (int x : chain) {
        g.verts[keep].insert(g.verts[keep].end(), g.verts[x].begin(), g.verts[x].end());
        g.verts[x].clear();
        gone[x] = 1;
      }
      for (auto it = g.edges.begin(); it != g.edges.end();)
        it = gone[it->first] || gone[it->second] ? g.edges.erase(it) : std::next(it);
      break;
    }
  }
  if (std::find(gone.begin(), gone.end(), 1) == gone.end()) return;
  Graph out;
  std::vector<int> id(g.pos.size(), -1);
  for (size_t x = 0; x < g.pos.size(); ++x)
    if (!gone[x]) {
      id[x] = int(out.pos.size());
      out.pos.push_back(g.pos[x]);
      out.fallback.push_back(g.fallback[x]);
      out.verts.push_back(std::move(g.verts[x]));
    }
  for (const auto& e : g.edges) out.edges.insert({id[e.first], id[e.second]});
  g = std::move(out);
}

// Junctions go to the centre of the largest inside ball among the poles of the vertices they
// own: the cluster a surgery leaves at a junction changes with the tessellation, the widest
// ball of the crossing region much less, and two models of one shape then get junctions in the
// same place (what texture transfer needs). A move that would put an edge outside is skipped.
void centre_junctions(Graph& g, const Eigen::MatrixX3d& V, const Eigen::MatrixX3d& poles, const InsideMesh& in,
                      double opt_reach) {
  std::vector<std::vector<int>> adj(g.pos.size());
  for (const auto& e : g.edges) adj[e.first].push_back(e.second), adj[e.second].push_back(e.first);
  for (size_t a = 0; a < g.pos.size(); ++a) {
    if (adj[a].size() < 3) continue;
    int best = -1;
    double widest = -1;
    for (int v : g.verts[a]) {
      const double r = (poles.row(v) - V.row(v)).squaredNorm();
      if (r > widest) widest = r, best = v;
    }
    // Only within the ball: further away the widest ball belongs to a branch, not the crossing.
    if (best < 0 || (poles.row(best).transpose() - g.pos[a]).squaredNorm() > opt_reach * opt_reach * widest) continue;
    const Eigen::Vector3d p = poles.row(best);
    bool ok = in.inside(p);
    for (int b : adj[a]) ok = ok && !in.segment_crosses(p, g.pos[b]);
    if (ok) g.pos[a] = p;
  }
}

// A part whose skeleton shrank to a single node (a ball-like part, where every edge is shorter
// than the local radius) would get no segment, and the layout would drop its surface: the node is
// split in two along the principal axis of its vertices, each half owning its side.
void split_lone_node(Graph& g, const Eigen::MatrixX3d& X, const InsideMesh& in) {
  if (g.pos.size() != 1 || !g.edges.empty() || g.verts[0].size() < 2) return;
  const std::vector<int>& vs = g.verts[0];
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int v : vs) c += X.row(v).transpose();
  c /= double(vs.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int v : vs) {
    const Eigen::Vector3d d = X.row(v).transpose() - c;
    cov += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Eigen::Vector3d axis = eig.eigenvectors().col(2);
  // The sign of an eigenvector is arbitrary: take the one towards the longer side, so that a
  // rotated input gives the rotated skeleton.
  double lo = 0, hi = 0;
  for (int v : vs) {
    const double t = (X.row(v).transpose() - c).dot(axis);
    lo = std::min(lo, t), hi = std::max(hi, t);
  }
  if (-lo > hi) axis = -axis, std::swap(lo, hi), lo = -lo, hi = -hi;
  Eigen::Vector3d a = c + 0.5 * lo * axis, b = c + 0.5 * hi * axis;
  for (int k = 0; k < 8 && !(in.inside(a) && in.inside(b) && in.segment_inside(a, b)); ++k)
    a = c + 0.5 * (a - c), b = c + 0.5 * (b - c);
  Graph out;
  out.pos = {a, b};
  out.fallback = {g.fallback[0], g.fallback[0]};
  out.verts.resize(2);
  for (int v : vs) out.verts[(X.row(v).transpose() - c).dot(axis) >= 0 ? 1 : 0].push_back(v);
  if (out.verts[0].empty() || out.verts[1].empty()) return;
  out.edges.insert({0, 1});
  g = std::move(out);
}

// How far the skeleton is from explaining the surface as tubes around it: the area-weighted mean
// over vertices of | distance to the skeleton - medial radius |. A missing limb leaves its
// vertices far from every edge; a skeleton through the middle of the volume keeps each vertex at
// about its inscribed-ball radius.
double tube_error(const Graph& g, const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::MatrixX3d& poles) {
  std::vector<double> w(V.rows(), 0.0);
  for (int f = 0; f < F.rows(); ++f) {
    const double a = (V.row(F(f, 1)) - V.row(F(f, 0))).cross(V.row(F(f, 2)) - V.row(F(f, 0))).norm();
    for (int k = 0; k < 3; ++k) w[F(f, k)] += a;
  }
  double sum = 0, wsum = 0;
  for (int i = 0; i < V.rows(); ++i) {
    const Eigen::Vector3d p = V.row(i);
    double d = INFINITY;
    for (const auto& e : g.edges) {
      const Eigen::Vector3d a = g.pos[e.first], b = g.pos[e.second];
      const Eigen::Vector3d ab = b - a;
      const double len2 = ab.squaredNorm();
      const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      d = std::min(d, (a + t * ab - p).norm());
    }
    for (const auto& q : g.pos) d = std::min(d, (q - p).norm());
    const double r = (poles.row(i) - V.row(i)).norm();
    sum += w[i] * std::abs(d - r);
    wsum += w[i];
  }
  return wsum > 0 ? sum / wsum : 0.0;
}

}  // namespace

Skeleton extract_skeleton(const Mesh& mesh, const SkeletonOptions& opt, const Progress& progress, SkeletonStats* stats) {
  const auto start = Clock::now();
  SkeletonStats st;
  Skeleton sk;
  const Eigen::MatrixX3d V = vertex_matrix(mesh);
  const Eigen::MatrixX3i F = face_matrix(mesh);
  const int n = int(V.rows()), m = int(F.rows());
  sk.vertex_node.assign(n, -1);
  // Connected parts, numbered by their smallest vertex.
  std::vector<int> comp(n);
  std::iota(comp.begin(), comp.end(), 0);
  auto find = [&](int x) {
    while (comp[x] != x) x = comp[x] = comp[comp[x]];
    return x;
  };
  for (int f = 0; f < m; ++f)
    for (int k = 1; k < 3; ++k) {
      const int a = find(F(f, 0)), b = find(F(f, k));
      if (a != b) comp[std::max(a, b)] = std::min(a, b);
    }
  std::map<int, std::vector<int>> part_faces;
  for (int f = 0; f < m; ++f) part_faces[find(F(f, 0))].push_back(f);

  for (const auto& [root, fs] : part_faces) {
    (void)root;
    ++st.parts;
    std::vector<int> local(n, -1), global;
    Eigen::MatrixX3i PF(fs.size(), 3);
    for (size_t r = 0; r < fs.size(); ++r)
      for (int k = 0; k < 3; ++k) {
        const int v = F(fs[r], k);
        if (local[v] < 0) local[v] = int(global.size()), global.push_back(v);
        PF(r, k) = local[v];
      }
    Eigen::MatrixX3d PV(global.size(), 3);
    for (size_t i = 0; i < global.size(); ++i) PV.row(i) = V.row(global[i]);
    const double diag = (PV.colwise().maxCoeff() - PV.colwise().minCoeff()).norm();

    auto t0 = Clock::now();
    // Large parts are contracted through a proxy (cotangent weights); parts up to the proxy's size
    // as they are, with the raw contraction options (uniform weights by default).
    const bool use_proxy = opt.proxy_max_vertices > 0 && PV.rows() > opt.proxy_max_vertices;
    Eigen::MatrixX3d XV = PV;
    Eigen::MatrixX3i XF = PF;
    if (use_proxy) make_proxy(PV, PF, opt, XV, XF);
    st.proxy_vertices += int(XV.rows());
    st.proxy_seconds += seconds_since(t0);
    st.contraction_seconds += seconds_since(t0);
    const bool run_contraction = opt.method != SkeletonMethod::medial;
    const bool run_medial = opt.method != SkeletonMethod::contraction;
    // The medial poles are the medial candidate's contracted shape and, for both candidates, the
    // radius the skeleton should keep from the surface. The second thread starts on them while
    // the contraction runs, and the contraction's thread joins in once it is done: the poles are
    // on the medial candidate's critical path, the contraction's surgery is not. Vertices are
    // independent, so the split does not change them.
    const TriangleBvh surface(PV, PF, {}, 8);  // wide leaves: it serves the poles' ball queries
    const MedialPoles pole_finder(XV, XF, use_proxy ? nullptr : &surface);
    Eigen::MatrixX3d poles(XV.rows(), 3);
    const int pole_chunk = 32, pole_chunks = int((XV.rows() + pole_chunk - 1) / pole_chunk);
    std::atomic<int> next_chunk{0};
    int chunks_done = 0;
    std::exception_ptr poles_failure;
    std::mutex poles_mutex;
    std::condition_variable poles_cv;
    double poles_seconds = 0;  // summed over the threads that took part
    auto work_on_poles = [&] {
      const auto t = Clock::now();
      int finished = 0;
      std::exception_ptr failure;
      for (int c; (c = next_chunk++) < pole_chunks;) {
        try {
          for (int i = c * pole_chunk; i < std::min<int>(int(XV.rows()), (c + 1) * pole_chunk); ++i)
            poles.row(i) = pole_finder.pole(i);
        } catch (...) {
          failure = std::current_exception();
        }
        ++finished;
      }
      std::lock_guard<std::mutex> lock(poles_mutex);
      poles_seconds += seconds_since(t);
      if (failure && !poles_failure) poles_failure = failure;
      chunks_done += finished;
      if (chunks_done == pole_chunks) poles_cv.notify_all();
    };
    auto wait_for_poles = [&] {
      std::unique_lock<std::mutex> lock(poles_mutex);
      poles_cv.wait(lock, [&] { return chunks_done == pole_chunks; });
      if (poles_failure) std::rethrow_exception(poles_failure);
    };

    // The inside tests are first needed by a surgery, well after the poles have started: they
    // are built on this thread while the second one starts on the poles.
    std::optional<InsideMesh> inside;
    std::promise<void> inside_built;
    const std::shared_future<void> inside_ready = inside_built.get_future().share();
    // Genus of the part from its Euler characteristic (closed: E = 3F/2).
    const int genus = int((2 - PV.rows() + PF.rows() / 2) / 2);
    struct Candidate {
      Graph g;
      int cycles = 0, outside = 0;
      double error = INFINITY;
      SkeletonStats st;  // this candidate's share of the work
    };
    std::mutex progress_mutex;  // the candidates report from two threads
    const Progress say = progress ? Progress([&](const std::string& line) {
      std::lock_guard<std::mutex> lock(progress_mutex);
      progress(line);
    })
                                  : Progress();
    auto degrees = [](const Graph& g) {
      std::vector<int> deg(g.pos.size(), 0);
      for (const auto& e : g.edges) ++deg[e.first], ++deg[e.second];
      return deg;
    };
    auto cut = [&](const Eigen::MatrixX3d& contracted, const char* name, Candidate& c) {
      std::shared_future<void>(inside_ready).get();  // each thread waits through its own copy
      const InsideMesh& in = *inside;
      const auto t = Clock::now();
      c.g = surgery(XV, contracted, XF, in, genus, opt, c.st);
      c.st.surgery_seconds += seconds_since(t);
      if (say) {
        const std::vector<int> deg = degrees(c.g);
        say(std::string(name) + " surgery: " + std::to_string(c.g.pos.size()) + " nodes, " +
            std::to_string(c.g.edges.size()) + " edges, " + std::to_string(std::count(deg.begin(), deg.end(), 1)) +
            " ends, refused " + std::to_string(c.st.refused_collapses) + ", forced " + std::to_string(c.st.forced_collapses));
      }
    };
    // Refinement needs the poles (bent edges, tube error).
    auto finish = [&](const char* name, Candidate& c) {
      const InsideMesh& in = *inside;  // built: the candidate's surgery waited for it
      const auto t = Clock::now();
      refine(c.g, XV, in, surface, diag, opt);
      if (opt.centre_junctions > 0) centre_junctions(c.g, XV, poles, in, opt.centre_junctions);
      bend_crossing_edges(c.g, in, poles);
      c.cycles = int(c.g.edges.size()) - int(c.g.pos.size()) + 1;
      for (const auto& e : c.g.edges)
        if (!in.segment_inside(c.g.pos[e.first], c.g.pos[e.second])) ++c.outside;
      if (opt.method == SkeletonMethod::automatic) c.error = tube_error(c.g, XV, XF, poles) / std::max(diag, 1e-300);
      c.st.refinement_seconds += seconds_since(t);
      if (say) {
        char line[200];
        const std::vector<int> deg = degrees(c.g);
        std::snprintf(line, sizeof line,
                      "%s skeleton: %zu nodes, %d ends, %d cycles (genus %d), %d edges outside, tube error %.4f", name,
                      c.g.pos.size(), int(std::count(deg.begin(), deg.end(), 1)), c.cycles, genus, c.outside, c.error);
        say(line);
      }
    };
    // Two candidates: Au et al.'s contraction, which keeps the cycles of CAD parts but can pull short
    // limbs into the body, and the medial poles, which keep every limb but make sheets of thin
    // walls. They are independent, so the medial one is built on a second thread.
    Candidate contraction, medial;
    std::exception_ptr medial_failure;
    std::thread medial_thread([&] {
      try {
        work_on_poles();
        wait_for_poles();
        if (!run_medial) return;
        // The poles scatter where the surface is noisy or flat: a few steps of umbrella smoothing
        // over the mesh's connectivity tidy them before the surgery.
        Eigen::MatrixX3d smooth = poles;
        std::vector<std::vector<int>> nb(XV.rows());
        for (int f = 0; f < XF.rows(); ++f)
          for (int k = 0; k < 3; ++k) nb[XF(f, k)].push_back(XF(f, (k + 1) % 3)), nb[XF(f, (k + 1) % 3)].push_back(XF(f, k));
        for (int step = 0; step < opt.medial_smoothing; ++step) {
          Eigen::MatrixX3d next = smooth;
          for (int i = 0; i < XV.rows(); ++i) {
            if (nb[i].empty()) continue;
            Eigen::RowVector3d c = Eigen::RowVector3d::Zero();
            for (int j : nb[i]) c += smooth.row(j);
            next.row(i) = 0.5 * smooth.row(i) + 0.5 * c / double(nb[i].size());
          }
          smooth = std::move(next);
        }
        cut(smooth, "medial", medial);
        finish("medial", medial);
      } catch (...) {
        medial_failure = std::current_exception();
      }
    });
    try {
      inside.emplace(PV, PF);
      inside_built.set_value();
    } catch (...) {
      inside_built.set_exception(std::current_exception());
    }
    std::exception_ptr contraction_failure;
    try {
      if (run_contraction) {
        const auto t = Clock::now();
        const ContractResult cr = contract_mesh(XV, XF, use_proxy ? opt.contraction : opt.raw_contraction, say);
        st.iterations = std::max(st.iterations, cr.iterations);
        st.contraction_seconds += seconds_since(t);
        work_on_poles();
        cut(cr.positions, "contraction", contraction);
        wait_for_poles();
        finish("contraction", contraction);
      } else {
        work_on_poles();
      }
    } catch (...) {
      contraction_failure = std::current_exception();
    }
    medial_thread.join();
    if (contraction_failure) std::rethrow_exception(contraction_failure);
    if (medial_failure) std::rethrow_exception(medial_failure);
    st.medial_seconds += poles_seconds;
    st.contraction_seconds += poles_seconds;
    for (const Candidate* c : {&contraction, &medial}) {
      st.surgery_seconds += c->st.surgery_seconds;
      st.refinement_seconds += c->st.refinement_seconds;
      st.refused_collapses += c->st.refused_collapses;
      st.forced_collapses += c->st.forced_collapses;
    }
    // The medial candidate must halve the error to win on it alone: where both explain the
    // surface, the contraction's skeleton is the smoother one (the poles of flat caps and of
    // noisy surfaces scatter). With more ends and a smaller error it wins too: those ends are
    // limbs the contraction pulled in.
    auto rank = [&](const Candidate& c, double handicap) {
      return std::make_tuple(c.g.edges.empty(), c.cycles != genus, c.outside, c.error * handicap);
    };
    auto ends = [](const Graph& g) {
      std::vector<int> deg(g.pos.size(), 0);
      for (const auto& e : g.edges) ++deg[e.first], ++deg[e.second];
      return std::count(deg.begin(), deg.end(), 1);
    };
    const bool more_limbs = rank(medial, 1.0) < rank(contraction, 1.0) && ends(medial.g) > ends(contraction.g);
    Candidate& best = !run_medial ? contraction
                      : !run_contraction || more_limbs || rank(medial, opt.medial_handicap) < rank(contraction, 1.0)
                          ? medial
                          : contraction;
    if (&best == &medial) ++st.medial_parts;
    Graph& g = best.g;
    split_lone_node(g, XV, *inside);
    st.outside_edges += best.outside;
    const auto t1 = Clock::now();
    std::vector<int> owner(PV.rows());
    if (use_proxy) {
      owner = map_to_nodes(PV, PF, XV, XF, g);
    } else {
      for (size_t a = 0; a < g.verts.size(); ++a)
        for (int v : g.verts[a]) owner[v] = int(a);
    }
    st.proxy_seconds += seconds_since(t1);

    const int base = int(sk.nodes.size());
    for (size_t a = 0; a < g.pos.size(); ++a) sk.nodes.push_back(g.pos[a]);
    for (size_t v = 0; v < global.size(); ++v) sk.vertex_node[global[v]] = base + owner[v];
    for (const auto& e : g.edges) sk.edges.push_back({base + e.first, base + e.second});
  }
  st.seconds = seconds_since(start);
  if (stats) *stats = st;
  return sk;
}

}  // namespace sdm
