#include "libstm/mesh/repair_soup.h"

#include "libstm/core/errors.h"
#include "libstm/core/union_find.h"
#include "libstm/mesh/edge_table.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>

namespace sdm {

long RepairReport::count(const std::string& kind) const {
  for (const auto& s : steps)
    if (s.kind == kind) return s.count;
  return 0;
}

long RepairReport::faces_dropped() const {
  long n = 0;
  for (const auto& s : steps)
    if (s.kind.rfind("faces dropped", 0) == 0) n += s.count;
  return n;
}

nlohmann::json RepairReport::to_json() const {
  nlohmann::json j;
  j["changed"] = changed();
  j["weld_distance"] = weld_distance;
  j["steps"] = nlohmann::json::array();
  for (const auto& s : steps) j["steps"].push_back({{"kind", s.kind}, {"count", s.count}, {"example", s.example}});
  return j;
}

namespace {

void note(RepairReport& r, const std::string& kind, long count, const std::string& example) {
  if (count > 0) r.steps.push_back({kind, count, example});
}

// Keeps the triangles with keep[f] (their uv and sources along).
void keep_faces(MeshSoup& soup, std::vector<int>& source, const std::vector<char>& keep) {
  const bool uv = soup.uv.size() == 3 * soup.triangles.size();
  size_t n = 0;
  for (size_t f = 0; f < soup.triangles.size(); ++f) {
    if (!keep[f]) continue;
    soup.triangles[n] = soup.triangles[f], source[n] = source[f];
    if (uv)
      for (size_t c = 0; c < 3; ++c) soup.uv[3 * n + c] = soup.uv[3 * f + c];
    ++n;
  }
  soup.triangles.resize(n), source.resize(n);
  if (uv) soup.uv.resize(3 * n);
}

void rename_corners(MeshSoup& soup, const std::vector<int>& rep) {
  for (auto& t : soup.triangles)
    for (int& v : t) v = rep[size_t(v)];
}

// The bits of a coordinate, -0 and +0 alike.
uint64_t coordinate_bits(double x) {
  uint64_t u = 0;
  x = x == 0 ? 0.0 : x;
  std::memcpy(&u, &x, sizeof u);
  return u;
}

// Sorts keys by their high 32 bits, stably (three passes of a least-significant-digit radix sort:
// keys made in increasing order of their low bits stay in that order within equal high bits).
void radix_sort_high32(std::vector<uint64_t>& keys) {
  std::vector<uint64_t> other(keys.size());
  for (int shift : {32, 43, 54}) {
    std::vector<size_t> count(2049, 0);
    for (uint64_t k : keys) ++count[((k >> shift) & 2047) + 1];
    for (size_t d = 0; d < 2048; ++d) count[d + 1] += count[d];
    for (uint64_t k : keys) other[count[(k >> shift) & 2047]++] = k;
    keys.swap(other);
  }
}

// Exact weld: every used point onto the lowest-numbered point with the same coordinates. The
// points sorted by a 32-bit hash of their coordinates (a radix sort: a tenth of the time of sorting
// pairs of 64-bit hashes, a thirtieth of sorting by coordinates), equal coordinates then found
// within each run of equal hashes, in the points' order. `used`: the soup's used_points. Returns
// the number of points welded away.
long weld_exact(MeshSoup& soup, const std::vector<char>& used, std::string& example) {
  const auto& p = soup.points;
  std::vector<uint64_t> order;  // (hash << 32) | point
  order.reserve(p.size());
  for (size_t i = 0; i < used.size(); ++i) {
    if (!used[i]) continue;
    uint64_t h = 0x9E3779B97F4A7C15ull;
    for (int c = 0; c < 3; ++c) h = (h ^ coordinate_bits(p[i][c])) * 0xFF51AFD7ED558CCDull, h ^= h >> 29;
    order.push_back((h & 0xffffffff00000000ull) | uint64_t(i));
  }
  radix_sort_high32(order);
  std::vector<int> rep(p.size());
  std::iota(rep.begin(), rep.end(), 0);
  long welded = 0;
  auto point = [&](size_t k) { return int(order[k] & 0xffffffffu); };
  for (size_t run = 0, end = 0; run < order.size(); run = end) {
    for (end = run + 1; end < order.size() && order[end] >> 32 == order[run] >> 32;) ++end;
    for (size_t i = run + 1; i < end; ++i)  // runs hold one point but where coordinates repeat
      for (size_t j = run; j < i; ++j) {
        const int a = point(j), b = point(i);
        if (rep[size_t(a)] != a || p[size_t(a)] != p[size_t(b)]) continue;
        rep[size_t(b)] = a;
        if (!welded++) example = "vertex " + std::to_string(b) + " onto vertex " + std::to_string(a);
        break;
      }
  }
  if (welded) rename_corners(soup, rep);
  return welded;
}

// The points on an edge that one face alone uses (the rim of a crack or a hole).
std::vector<int> boundary_points(const MeshSoup& soup, const EdgeTable& t) {
  std::vector<char> on(soup.points.size(), 0);
  for (size_t e = 0; e < t.edges(); ++e)
    if (t.uses(e) == 1) on[size_t(t.lo[t.group[e]])] = on[size_t(t.hi[t.group[e]])] = 1;
  std::vector<int> out;
  for (size_t v = 0; v < on.size(); ++v)
    if (on[v]) out.push_back(int(v));
  return out;
}

// Boundary points within `tol` of each other welded (onto the lowest-numbered of each cluster),
// through a grid of cells `tol` wide: each point meets the points of the 27 cells around its own.
long weld_boundary(MeshSoup& soup, const EdgeTable& table, double tol, std::string& example) {
  if (!(tol > 0)) return 0;
  const std::vector<int> rim = boundary_points(soup, table);
  if (rim.size() < 2) return 0;
  for (int v : rim)  // cells numbered in 64 bits: a model far from the origin for its size keeps exact welds only
    if (soup.points[size_t(v)].cwiseAbs().maxCoeff() / tol > 1e15) return 0;
  using Key = std::array<int64_t, 3>;
  auto key = [&](int v) {
    const Eigen::Vector3d& x = soup.points[size_t(v)];
    return Key{int64_t(std::floor(x[0] / tol)), int64_t(std::floor(x[1] / tol)), int64_t(std::floor(x[2] / tol))};
  };
  std::vector<std::pair<Key, int>> cells;
  for (int v : rim) cells.push_back({key(v), v});
  std::sort(cells.begin(), cells.end());
  UnionFind uf(soup.points.size());
  for (int v : rim) {
    const Key k = key(v);
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy)
        for (int64_t dz = -1; dz <= 1; ++dz) {
          const Key n{k[0] + dx, k[1] + dy, k[2] + dz};
          auto it = std::lower_bound(cells.begin(), cells.end(), std::make_pair(n, -1));
          for (; it != cells.end() && it->first == n; ++it)
            if (it->second != v && (soup.points[size_t(it->second)] - soup.points[size_t(v)]).norm() <= tol) uf.unite(it->second, v);
        }
  }
  std::vector<int> lowest(soup.points.size(), INT32_MAX), rep(soup.points.size());
  for (int v : rim) lowest[size_t(uf.find(v))] = std::min(lowest[size_t(uf.find(v))], v);
  std::iota(rep.begin(), rep.end(), 0);
  long welded = 0;
  for (int v : rim) {
    rep[size_t(v)] = lowest[size_t(uf.find(v))];
    if (rep[size_t(v)] != v && !welded++) example = "vertex " + std::to_string(v) + " onto vertex " + std::to_string(rep[size_t(v)]);
  }
  if (welded) rename_corners(soup, rep);
  return welded;
}

// The corner of triangle t that is neither a nor b.
int third_corner(const std::array<int, 3>& t, int a, int b) {
  for (int v : t)
    if (v != a && v != b) return v;
  return t[0];
}

// Drops the triangles with a repeated corner (collapsed by a weld or so in the file). Returns
// whether it dropped any.
bool drop_collapsed(MeshSoup& soup, std::vector<int>& source, RepairReport& r) {
  std::vector<char> keep(soup.triangles.size(), 1);
  long repeated = 0;
  std::string example;
  for (size_t f = 0; f < soup.triangles.size(); ++f) {
    const auto& t = soup.triangles[f];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) {
      keep[f] = 0;
      if (!repeated++) example = "face " + std::to_string(source[f]);
    }
  }
  if (!repeated) return false;
  for (auto& step : r.steps)
    if (step.kind.rfind("faces dropped: a repeated corner", 0) == 0) {
      step.count += repeated;  // a second weld's: one step
      repeated = 0;
    }
  note(r, "faces dropped: a repeated corner (collapsed by the weld or in the file)", repeated, example);
  keep_faces(soup, source, keep);
  return true;
}

// Drops the repeats of a triangle (the same three corners in either orientation; the first kept),
// found as faces of one edge with the same third corner. `everywhere` false: only on the edges a
// duplicate makes crowded (more than two faces) or inconsistent (two faces the same way), where
// every duplicate shows but two faces back to back with no other neighbour. Returns, per face,
// whether it is kept, or an empty vector when none was dropped.
std::vector<char> drop_duplicated(MeshSoup& soup, std::vector<int>& source, const EdgeTable& t, bool everywhere, RepairReport& r) {
  std::vector<char> keep(soup.triangles.size(), 1);
  long duplicated = 0;
  std::string example;
  for (size_t e = 0; e < t.edges(); ++e) {
    const size_t b = t.group[e], n = t.uses(e);
    if (n < 2 || (!everywhere && n == 2 && t.forward[b] != t.forward[b + 1])) continue;
    for (size_t i = b; i + 1 < b + n; ++i)
      for (size_t j = i + 1; j < b + n; ++j) {
        const int f = t.face(i), g = t.face(j);
        const int first = std::min(f, g), repeat = std::max(f, g);
        if (!keep[size_t(repeat)] || !keep[size_t(first)]) continue;
        if (third_corner(soup.triangles[size_t(f)], t.lo[i], t.hi[i]) != third_corner(soup.triangles[size_t(g)], t.lo[j], t.hi[j])) continue;
        keep[size_t(repeat)] = 0;
        if (!duplicated++) example = "face " + std::to_string(source[size_t(repeat)]) + " repeats face " + std::to_string(source[size_t(first)]);
      }
  }
  note(r, "faces dropped: duplicates of another face", duplicated, example);
  if (!duplicated) return {};
  keep_faces(soup, source, keep);
  return keep;
}

// Pairs the faces of one edge used more than twice (entries [b, e) of the table). Sorted by the
// angle of their third corner about the edge (lo -> hi), a face running lo -> hi faces the next
// angle, one running hi -> lo the previous: a face of the second kind followed by one of the
// first encloses a volume between them, so they are matched like brackets around the circle. The
// faces left over keep the edge as a border of their own. Returns the number left over.
long pair_around_edge(const MeshSoup& soup, const EdgeTable& t, size_t b, size_t e, std::vector<int>& mate) {
  const Eigen::Vector3d o = soup.points[size_t(t.lo[b])], d = (soup.points[size_t(t.hi[b])] - o).normalized();
  std::vector<std::pair<double, size_t>> around;
  Eigen::Vector3d u = Eigen::Vector3d::Zero(), v = Eigen::Vector3d::Zero();
  for (size_t i = b; i < e; ++i) {
    Eigen::Vector3d w = soup.points[size_t(third_corner(soup.triangles[size_t(t.face(i))], t.lo[i], t.hi[i]))] - o;
    w -= d * w.dot(d);
    if (u.squaredNorm() == 0 && w.squaredNorm() > 0) u = w.normalized(), v = d.cross(u);
    around.push_back({std::atan2(w.dot(v), w.dot(u)), i});
  }
  std::sort(around.begin(), around.end());
  const size_t n = around.size();
  // Start after the lowest running count of open brackets, so that every match closes in one turn.
  size_t start = 0;
  for (long depth = 0, lowest = 0, k = 0; k < long(n); ++k) {
    depth += t.forward[around[size_t(k)].second] ? -1 : 1;
    if (depth < lowest) lowest = depth, start = size_t(k) + 1;
  }
  std::vector<size_t> open;
  long pairs = 0;
  for (size_t k = 0; k < n; ++k) {
    const size_t i = around[(start + k) % n].second;
    if (!t.forward[i]) open.push_back(i);
    else if (!open.empty()) mate[size_t(t.halfedge[i])] = t.halfedge[open.back()], mate[size_t(t.halfedge[open.back()])] = t.halfedge[i], open.pop_back(), ++pairs;
  }
  if (pairs == 0) {  // all run one way (faces flipped as well): the two first around the edge
    const int x = t.halfedge[around[0].second], y = t.halfedge[around[1].second];
    mate[size_t(x)] = y, mate[size_t(y)] = x, pairs = 1;
  }
  return long(n) - 2 * pairs;
}

// A side peeled off a crowded edge, with a side of a pair kept there.
struct Peeled {
  int side, kept;
};

// The glued partner of every face side (3 f + c, from corner c to c + 1), or -1 on a border;
// `peeled` receives the sides left over at crowded edges.
std::vector<int> glue_sides(const MeshSoup& soup, const EdgeTable& t, RepairReport& r, std::vector<Peeled>& peeled_sides) {
  std::vector<int> mate(3 * soup.triangles.size(), -1);
  long crowded = 0;
  std::string example;
  for (size_t e = 0; e < t.edges(); ++e) {
    const size_t b = t.group[e], uses = t.uses(e);
    if (uses == 2) mate[size_t(t.halfedge[b])] = t.halfedge[b + 1], mate[size_t(t.halfedge[b + 1])] = t.halfedge[b];
    if (uses <= 2) continue;
    const long left = pair_around_edge(soup, t, b, b + uses, mate);
    int kept = -1;
    for (size_t i = b; i < b + uses; ++i)
      if (mate[size_t(t.halfedge[i])] >= 0) kept = t.halfedge[i];
    for (size_t i = b; i < b + uses; ++i)
      if (mate[size_t(t.halfedge[i])] < 0) peeled_sides.push_back({t.halfedge[i], kept});
    if (!crowded++)
      example = "edge (" + std::to_string(t.lo[b]) + ", " + std::to_string(t.hi[b]) + ") of " + std::to_string(uses) + " faces: " +
                std::to_string((long(uses) - left) / 2) + " pair(s) kept, " + std::to_string(left) + " face(s) peeled off";
  }
  note(r, "non-manifold edges split (faces paired around the edge, the rest peeled off as a sheet)", crowded, example);
  note(r, "faces peeled off non-manifold edges (their edge now a border)", long(peeled_sides.size()), "");
  return mate;
}

// Whether sides s and its mate run the same way along their edge (then one face must flip).
bool same_direction(const MeshSoup& soup, int s, int m) {
  return soup.triangles[size_t(s / 3)][size_t(s % 3)] == soup.triangles[size_t(m / 3)][size_t(m % 3)];
}

// Per face, whether it flips so that its part agrees with the majority of its faces: a breadth-first
// walk over the glued sides; a side whose faces cannot agree (a one-sided part) is unglued.
std::vector<char> orient_parts(const MeshSoup& soup, std::vector<int>& mate, RepairReport& r) {
  const size_t nf = soup.triangles.size();
  std::vector<char> flip(nf, 0), seen(nf, 0);
  std::vector<int> part;
  long flipped = 0, cut = 0;
  std::string flip_example, cut_example;
  for (size_t seed = 0; seed < nf; ++seed) {
    if (seen[seed]) continue;
    part.assign(1, int(seed)), seen[seed] = 1;
    for (size_t q = 0; q < part.size(); ++q) {
      const int f = part[q];
      for (int c = 0; c < 3; ++c) {
        const int s = 3 * f + c, m = mate[size_t(s)];
        if (m < 0) continue;
        const int g = m / 3;
        const char want = char(flip[size_t(f)] ^ same_direction(soup, s, m));
        if (!seen[size_t(g)]) seen[size_t(g)] = 1, flip[size_t(g)] = want, part.push_back(g);
        else if (flip[size_t(g)] != want) {
          mate[size_t(s)] = mate[size_t(m)] = -1;
          if (!cut++) cut_example = "between faces " + std::to_string(f) + " and " + std::to_string(g);
        }
      }
    }
    size_t n = 0;
    for (int f : part) n += size_t(flip[size_t(f)]);
    const bool invert = 2 * n > part.size();
    for (int f : part) flip[size_t(f)] = char(flip[size_t(f)] ^ invert);
    const long turned = long(invert ? part.size() - n : n);
    if (turned > 0 && !flipped) flip_example = std::to_string(turned) + " in the part of face " + std::to_string(seed);
    flipped += turned;
  }
  note(r, "faces flipped to agree with the rest of their part", flipped, flip_example);
  note(r, "edges cut where a part cannot be oriented (one-sided)", cut, cut_example);
  return flip;
}


// The corner of face g at vertex v, given that g's side c runs between v and another vertex.
int corner_at(const MeshSoup& soup, int g, int c, int v) {
  return soup.triangles[size_t(g)][size_t(c)] == v ? 3 * g + c : 3 * g + (c + 1) % 3;
}

// The corners (3 f + k) grouped by fan: two faces glued along a side are in one fan at each of
// its two ends.
UnionFind fan_sets(const MeshSoup& soup, const std::vector<int>& mate) {
  UnionFind fans(3 * soup.triangles.size());
  for (size_t s = 0; s < mate.size(); ++s) {
    const int m = mate[s];
    if (m < int(s)) continue;  // each glued pair once; -1 skipped
    const int f = int(s) / 3, c = int(s) % 3, a = soup.triangles[size_t(f)][size_t(c)], b = soup.triangles[size_t(f)][size_t((c + 1) % 3)];
    fans.unite(3 * f + c, corner_at(soup, m / 3, m % 3, a));
    fans.unite(3 * f + (c + 1) % 3, corner_at(soup, m / 3, m % 3, b));
  }
  return fans;
}

// A face peeled off a crowded edge can still be joined to the pair kept there through its other
// sides, around both ends: the edge would then keep its three faces after the split. Such a
// face is cut from its neighbours at the edge's first end as well, so that it gets a copy of that
// vertex. Returns the number of faces so cut.
long detach_peeled(const MeshSoup& soup, std::vector<int>& mate, const std::vector<Peeled>& peeled) {
  long cut = 0;
  for (int pass = 0; pass < 8 && !peeled.empty(); ++pass) {
    UnionFind fans = fan_sets(soup, mate);
    long now = 0;
    for (const auto& [s, k] : peeled) {
      if (k < 0 || mate[size_t(k)] < 0) continue;
      const int f = s / 3, c = s % 3, a = soup.triangles[size_t(f)][size_t(c)], b = soup.triangles[size_t(f)][size_t((c + 1) % 3)];
      const bool joined = fans.find(corner_at(soup, f, c, a)) == fans.find(corner_at(soup, k / 3, k % 3, a)) &&
                          fans.find(corner_at(soup, f, c, b)) == fans.find(corner_at(soup, k / 3, k % 3, b));
      if (!joined) continue;
      const int other = 3 * f + (c + 2) % 3;  // f's other side at a: from its third corner to a
      if (mate[size_t(other)] >= 0) mate[size_t(mate[size_t(other)])] = -1, mate[size_t(other)] = -1, ++now;
    }
    cut += now;
    if (!now) break;
  }
  return cut;
}

// The points renumbered after the splits: the used input points in their order, then the copies
// (`copies`: the input point of each; `copy_of_corner[k]`: the copy corner k moves to, -1 for
// none); the flips applied; `point_source` gets each point's input point.
void renumber_points(MeshSoup& soup, const std::vector<int>& copy_of_corner, const std::vector<int>& copies,
                     const std::vector<char>& flip, RepairReport& r) {
  const size_t nf = soup.triangles.size();
  const std::vector<char> used = used_points(soup);
  std::vector<int> index(soup.points.size(), -1), source;
  for (size_t v = 0; v < soup.points.size(); ++v)
    if (used[v]) index[v] = int(source.size()), source.push_back(int(v));
  const int originals = int(source.size());
  source.insert(source.end(), copies.begin(), copies.end());
  for (size_t k = 0; k < 3 * nf; ++k) {
    int& v = soup.triangles[k / 3][k % 3];
    v = copy_of_corner[k] >= 0 ? originals + copy_of_corner[k] : index[size_t(v)];
  }
  const bool uv = soup.uv.size() == 3 * nf;
  for (size_t f = 0; f < nf; ++f)
    if (flip[f]) {
      std::swap(soup.triangles[f][1], soup.triangles[f][2]);
      if (uv) std::swap(soup.uv[3 * f + 1], soup.uv[3 * f + 2]);
    }
  std::vector<Eigen::Vector3d> points(source.size());
  for (size_t i = 0; i < source.size(); ++i) points[i] = soup.points[size_t(source[i])];
  if (soup.colors.size() == soup.points.size()) {
    std::vector<Eigen::Vector3f> colors(source.size());
    for (size_t i = 0; i < source.size(); ++i) colors[i] = soup.colors[size_t(source[i])];
    soup.colors = std::move(colors);
  }
  soup.points = std::move(points);
  r.point_source = std::move(source);
}

void note_splits(RepairReport& r, long split, size_t copies, const std::string& example) {
  note(r, "non-manifold vertices split (one copy per fan of faces)", split,
       split ? example + " (" + std::to_string(copies) + " vertices added in all)" : "");
}

// Every vertex split into one point per fan of faces glued around it (a copy for every fan but
// the one of the vertex's first corner, the copies numbered in the order of their first corner),
// the flips applied, the points renumbered (renumber_points).
void split_fans(MeshSoup& soup, const std::vector<int>& mate, const std::vector<char>& flip, RepairReport& r) {
  const size_t nf = soup.triangles.size();
  UnionFind fans = fan_sets(soup, mate);
  std::vector<int> copy_of_fan(3 * nf, -1), first_fan(soup.points.size(), -1), copy_of_corner(3 * nf, -1), copies;
  std::vector<char> was_split(soup.points.size(), 0);
  long split = 0;
  std::string example;
  for (size_t k = 0; k < 3 * nf; ++k) {
    const int v = soup.triangles[k / 3][k % 3], root = fans.find(int(k));
    if (first_fan[size_t(v)] < 0) first_fan[size_t(v)] = root;
    if (root == first_fan[size_t(v)]) continue;
    if (copy_of_fan[size_t(root)] < 0) {
      copy_of_fan[size_t(root)] = int(copies.size()), copies.push_back(v);
      if (!was_split[size_t(v)]) was_split[size_t(v)] = 1, example = split++ ? example : "vertex " + std::to_string(v);
    }
    copy_of_corner[k] = copy_of_fan[size_t(root)];
  }
  note_splits(r, split, copies.size(), example);
  renumber_points(soup, copy_of_corner, copies, flip, r);
}

// split_fans where only the vertices `pinched` have more than one fan: each one's corners grouped
// by fan through the glued sides at it; the same result as split_fans at a fraction of the cost.
void split_pinched(MeshSoup& soup, const std::vector<int>& mate, const std::vector<char>& flip, const std::vector<int>& pinched,
                   RepairReport& r) {
  const size_t nf = soup.triangles.size();
  std::vector<int> slot(soup.points.size(), -1);
  for (size_t i = 0; i < pinched.size(); ++i) slot[size_t(pinched[i])] = int(i);
  std::vector<std::vector<int>> corners(pinched.size());  // each vertex's corners, in increasing order
  for (size_t k = 0; k < 3 * nf; ++k)
    if (const int i = slot[size_t(soup.triangles[k / 3][k % 3])]; i >= 0) corners[size_t(i)].push_back(int(k));
  std::vector<std::pair<int, int>> fans;  // (first corner, input point) of every fan that gets a copy
  std::vector<int> copy_of_corner(3 * nf, -1), root_of;
  for (size_t i = 0; i < pinched.size(); ++i) {
    const std::vector<int>& ks = corners[i];
    const int v = pinched[i];
    UnionFind uf(ks.size());
    auto local = [&](int k) { return int(std::lower_bound(ks.begin(), ks.end(), k) - ks.begin()); };
    for (size_t a = 0; a < ks.size(); ++a) {
      const int f = ks[a] / 3, c = ks[a] % 3;
      for (int side : {3 * f + c, 3 * f + (c + 2) % 3})  // f's two sides at v
        if (const int m = mate[size_t(side)]; m >= 0) uf.unite(int(a), local(corner_at(soup, m / 3, m % 3, v)));
    }
    root_of.assign(ks.size(), -1);  // per root: the fan's number among `fans`, -2 for the first fan
    for (size_t a = 0; a < ks.size(); ++a) {
      int& fan = root_of[size_t(uf.find(int(a)))];
      if (fan == -1) {
        fan = a == 0 ? -2 : int(fans.size());
        if (a > 0) fans.push_back({ks[a], v});
      }
      copy_of_corner[size_t(ks[a])] = fan;  // a fan number for now
    }
  }
  // Copies numbered by their fan's first corner, as split_fans numbers them.
  std::vector<int> order(fans.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return fans[size_t(a)].first < fans[size_t(b)].first; });
  std::vector<int> number(fans.size()), copies;
  long split = 0;
  std::string example;
  std::vector<char> was_split(soup.points.size(), 0);
  for (int o : order) {
    const int v = fans[size_t(o)].second;
    number[size_t(o)] = int(copies.size()), copies.push_back(v);
    if (!was_split[size_t(v)]) was_split[size_t(v)] = 1, example = split++ ? example : "vertex " + std::to_string(v);
  }
  for (const auto& ks : corners)
    for (int k : ks) copy_of_corner[size_t(k)] = copy_of_corner[size_t(k)] >= 0 ? number[size_t(copy_of_corner[size_t(k)])] : -1;
  note_splits(r, split, copies.size(), example);
  renumber_points(soup, copy_of_corner, copies, flip, r);
}

bool repairable(const MeshSoup& soup) {
  for (const auto& p : soup.points)
    if (!p.allFinite()) return false;
  for (const auto& t : soup.triangles)
    for (int v : t)
      if (v < 0 || size_t(v) >= soup.points.size()) return false;
  return !soup.triangles.empty();
}

double diagonal_of_used(const MeshSoup& soup) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
  for (const auto& t : soup.triangles)
    for (int v : t) lo = lo.cwiseMin(soup.points[size_t(v)]), hi = hi.cwiseMax(soup.points[size_t(v)]);
  return (hi - lo).norm();
}

// The faces' numbers after keep_faces(keep): -1 for a dropped face.
std::vector<int> kept_index(const std::vector<char>& keep) {
  std::vector<int> index(keep.size(), -1);
  for (size_t f = 0, n = 0; f < keep.size(); ++f)
    if (keep[f]) index[f] = int(n++);
  return index;
}

}  // namespace

RepairReport repair_soup(MeshSoup& soup, const RepairOptions& options, const RepairHints& hints) {
  RepairReport r;
  r.face_source.resize(soup.triangles.size());
  std::iota(r.face_source.begin(), r.face_source.end(), 0);
  r.point_source.resize(soup.points.size());
  std::iota(r.point_source.begin(), r.point_source.end(), 0);
  if (!repairable(soup)) return r;
  const std::vector<char> used = used_points(soup);
  const long isolated = long(std::count(used.begin(), used.end(), char(0)));
  std::string example;
  bool welded = false;  // faces were renamed or dropped before the table: every step everywhere
  if (hints.borders) {
    const long n = weld_exact(soup, used, example);
    note(r, "coincident vertices welded (exact)", n, example);
    welded = n > 0;
  }
  welded |= drop_collapsed(soup, r.face_source, r);
  r.weld_distance = options.weld_tolerance * diagonal_of_used(soup);
  // One table for the rest, the validation's when nothing changed yet, made again only where faces change.
  EdgeTable table = hints.table && !welded ? EdgeTable() : edge_table(soup);
  const EdgeTable* t = hints.table && !welded ? hints.table : &table;
  if (long n = hints.borders ? weld_boundary(soup, *t, r.weld_distance, example) : 0) {
    note(r, "boundary vertices welded (within " + number(r.weld_distance) + ", " + number(options.weld_tolerance) + " of the diagonal)", n,
         example);
    drop_collapsed(soup, r.face_source, r);
    table = edge_table(soup), t = &table, welded = true;
  }
  const bool anywhere = welded || !hints.table;
  if (anywhere || hints.duplicated || hints.crowded_or_inconsistent) {
    const std::vector<char> keep = drop_duplicated(soup, r.face_source, *t, anywhere || hints.duplicated, r);
    if (!keep.empty()) table = without_faces(*t, kept_index(keep)), t = &table;
  }
  std::vector<Peeled> peeled;
  std::vector<int> mate = glue_sides(soup, *t, r, peeled);
  const bool orient = anywhere || hints.crowded_or_inconsistent;
  const std::vector<char> flip = orient ? orient_parts(soup, mate, r) : std::vector<char>(soup.triangles.size(), 0);
  note(r, "peeled faces cut from their neighbours too (still joined to the edge's pair around both ends)", detach_peeled(soup, mate, peeled), "");
  // Fans change only at the scanned vertices unless an edge was crowded or cut.
  const bool cut = r.count("edges cut where a part cannot be oriented (one-sided)") > 0 ||
                   r.count("non-manifold edges split (faces paired around the edge, the rest peeled off as a sheet)") > 0;
  if (hints.pinched && !anywhere && peeled.empty() && !cut) split_pinched(soup, mate, flip, *hints.pinched, r);
  else split_fans(soup, mate, flip, r);
  if (!soup.triangles.empty() && isolated) note(r, "isolated vertices dropped (in no face)", isolated, "");
  return r;
}

}  // namespace sdm
