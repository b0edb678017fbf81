#include "libstm/mesh/primitives.h"

#include "libstm/core/errors.h"
#include "libstm/geometry/differential_geometry.h"
#include "libstm/mesh/isotropic_remesh.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <unordered_map>

namespace sdm {
namespace {

using Vec = Eigen::Vector3d;
using Implicit = std::function<double(const Vec&)>;  // negative inside, close to a distance

// Vertex density of an equilateral triangulation with edge length L: sqrt(3)/2 L^2 of area per vertex.
const double kAreaPerVertex = std::sqrt(3.0) / 2.0;

// ---------------------------------------------------------------------------------------------
// Distance fields and their smooth union

double smooth_min(double a, double b, double k) {
  // Polynomial smooth minimum: C1, equal to min(a, b) once |a - b| > k.
  double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k * 0.25;
}

double capsule_sdf(const Vec& p, const Vec& a, const Vec& b, double r) {
  Vec ab = b - a;
  double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm() - r;
}

// Cylinder along coordinate axis `axis`, centred at c, radius r, half length hl, edges rounded
// with radius e.
double rounded_cylinder_sdf(const Vec& p, const Vec& c, int axis, double r, double hl, double e) {
  Vec q = p - c;
  double along = std::abs(q[axis]);
  double radial = std::hypot(q[(axis + 1) % 3], q[(axis + 2) % 3]);
  double dx = radial - (r - e), dy = along - (hl - e);
  return std::min(std::max(dx, dy), 0.0) + std::hypot(std::max(dx, 0.0), std::max(dy, 0.0)) - e;
}

// Torus around coordinate axis `axis` through c: major radius R, minor radius r.
double torus_sdf(const Vec& p, const Vec& c, int axis, double R, double r) {
  Vec q = p - c;
  double radial = std::hypot(q[(axis + 1) % 3], q[(axis + 2) % 3]);
  return std::hypot(radial - R, q[axis]) - r;
}

struct ImplicitShape {
  Implicit f;
  Vec lo, hi;          // bounding box of the surface
  double thinnest;     // smallest tube radius: the polygonisation grid must resolve it
};

ImplicitShape ypsilon_shape() {
  const double r = 0.22, k = 0.2;
  const Vec o(0, 0, 0), stem(0, -1.1, 0), left(-0.78, 0.78, 0), right(0.78, 0.78, 0);
  auto f = [=](const Vec& p) {
    double a = capsule_sdf(p, o, left, r), b = capsule_sdf(p, o, right, r), c = capsule_sdf(p, o, stem, r);
    // Arms first, then the stem, so that the Y is mirror-symmetric in x.
    return smooth_min(smooth_min(a, b, k), c, k);
  };
  return {f, Vec(-1.0, -1.32, -r), Vec(1.0, 1.0, r), r};
}

ImplicitShape bottle_shape() {
  auto f = [](const Vec& p) {
    double body = rounded_cylinder_sdf(p, Vec(0, 0, 0.8), 2, 0.6, 0.8, 0.2);
    double neck = capsule_sdf(p, Vec(0, 0, 1.4), Vec(0, 0, 2.3), 0.22);
    double handle = torus_sdf(p, Vec(0.62, 0, 0.85), 1, 0.42, 0.11);
    return smooth_min(smooth_min(body, neck, 0.25), handle, 0.08);
  };
  return {f, Vec(-0.6, -0.6, 0.0), Vec(1.15, 0.6, 2.52), 0.11};
}

ImplicitShape triple_torus_shape() {
  auto f = [](const Vec& p) {
    double a = torus_sdf(p, Vec(-1.7, 0, 0), 2, 1.0, 0.3), b = torus_sdf(p, Vec(0, 0, 0), 2, 1.0, 0.3),
           c = torus_sdf(p, Vec(1.7, 0, 0), 2, 1.0, 0.3);
    return smooth_min(smooth_min(a, c, 0.1), b, 0.1);
  };
  return {f, Vec(-3.0, -1.3, -0.3), Vec(3.0, 1.3, 0.3), 0.3};
}

ImplicitShape crossed_cylinders_shape() {
  auto f = [](const Vec& p) {
    double a = rounded_cylinder_sdf(p, Vec::Zero(), 0, 0.5, 2.0, 0.15);
    double b = rounded_cylinder_sdf(p, Vec::Zero(), 1, 0.5, 2.0, 0.15);
    return smooth_min(a, b, 0.2);
  };
  return {f, Vec(-2, -2, -0.5), Vec(2, 2, 0.5), 0.5};
}

// A thick bar along x (radius 0.8, length 3.2, ends rounded) with two small round tunnels through
// it along y (radius 0.15, at x = -0.7 and 0.7), their rims rounded: genus 2, each tunnel under a
// fifth of the bar's thickness (a bone with two small tunnels must keep a skeleton cycle per tunnel).
ImplicitShape two_tunnels_shape() {
  auto f = [](const Vec& p) {
    const double bar = rounded_cylinder_sdf(p, Vec::Zero(), 0, 0.8, 1.6, 0.2);
    const double a = std::hypot(p.x() + 0.7, p.z()) - 0.15, b = std::hypot(p.x() - 0.7, p.z()) - 0.15;
    return -smooth_min(-bar, smooth_min(a, b, 0.05), 0.05);  // the bar minus both tunnels, rims rounded
  };
  return {f, Vec(-1.6, -0.8, -0.8), Vec(1.6, 0.8, 0.8), 0.15};
}

// A mushroom: a thin cap (a spherical shell of radius 1 and thickness 0.16, above z = 0.35, its
// rim rounded) over a stem (a capsule of radius 0.2 from z = -1.1 up into the cap), joined
// smoothly: a sheet-like part over a tube, the hard case of a thin cap for the capsules.
ImplicitShape mushroom_shape() {
  auto f = [](const Vec& p) {
    const double shell = std::abs(p.norm() - 1.0) - 0.08, above = 0.35 - p.z();
    const double cap = -smooth_min(-shell, -above, 0.06);  // the shell cut above the plane, rim rounded
    const double stem = capsule_sdf(p, Vec(0, 0, -1.1), Vec(0, 0, 0.9), 0.2);
    return smooth_min(cap, stem, 0.15);
  };
  return {f, Vec(-1.08, -1.08, -1.3), Vec(1.08, 1.08, 1.08), 0.08};
}

// ---------------------------------------------------------------------------------------------
// Polygonisation: marching tetrahedra on a regular grid, each cube split into the six Kuhn
// tetrahedra around its main diagonal. The same split in every cube makes neighbouring cubes'
// faces agree, and with no grid value exactly on the surface (zero counts as outside) the
// piecewise-linear isosurface is a closed 2-manifold.

Mesh polygonize(const Implicit& f, const Vec& lo_in, const Vec& hi_in, double h) {
  // Smooth unions bulge out of the parts' boxes by up to k/4; the padding covers that.
  const Vec lo = lo_in - Vec::Constant(2 * h + 0.1);
  const Vec hi = hi_in + Vec::Constant(2 * h + 0.1);
  int n[3];
  for (int a = 0; a < 3; ++a) n[a] = static_cast<int>(std::ceil((hi[a] - lo[a]) / h)) + 1;
  auto gid = [&](int i, int j, int k) { return (static_cast<int64_t>(k) * n[1] + j) * n[0] + i; };
  auto gpos = [&](int64_t g) {
    int64_t i = g % n[0], j = (g / n[0]) % n[1], k = g / (static_cast<int64_t>(n[0]) * n[1]);
    return Vec(lo.x() + h * i, lo.y() + h * j, lo.z() + h * k);
  };
  std::vector<double> value(static_cast<size_t>(n[0]) * n[1] * n[2]);
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        double v = f(gpos(gid(i, j, k)));
        value[gid(i, j, k)] = v;
        bool on_border = i == 0 || j == 0 || k == 0 || i == n[0] - 1 || j == n[1] - 1 || k == n[2] - 1;
        if (on_border && v < 0) throw std::logic_error("primitive surface leaves its bounding box");
      }

  std::vector<Vec> points;
  std::vector<std::array<int, 3>> triangles;
  std::unordered_map<uint64_t, int> edge_vertex;
  auto crossing = [&](int64_t ga, int64_t gb) {
    if (ga > gb) std::swap(ga, gb);
    uint64_t key = static_cast<uint64_t>(ga) * static_cast<uint64_t>(value.size()) + static_cast<uint64_t>(gb);
    auto it = edge_vertex.find(key);
    if (it != edge_vertex.end()) return it->second;
    double fa = value[ga], fb = value[gb];
    // Kept away from the grid vertices so that no triangle is degenerate; projection onto the
    // surface follows anyway.
    double t = std::clamp(fa / (fa - fb), 0.05, 0.95);
    points.push_back(gpos(ga) + t * (gpos(gb) - gpos(ga)));
    int id = static_cast<int>(points.size()) - 1;
    edge_vertex.emplace(key, id);
    return id;
  };
  static const int kTets[6][4] = {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}};
  auto emit = [&](int64_t e0a, int64_t e0b, int64_t e1a, int64_t e1b, int64_t e2a, int64_t e2b, const Vec& outward) {
    // Orientation from the edge midpoints, which never form a degenerate triangle, so that it is
    // consistent everywhere even where the interpolated triangle is nearly flat.
    Vec m0 = 0.5 * (gpos(e0a) + gpos(e0b)), m1 = 0.5 * (gpos(e1a) + gpos(e1b)), m2 = 0.5 * (gpos(e2a) + gpos(e2b));
    int v0 = crossing(e0a, e0b), v1 = crossing(e1a, e1b), v2 = crossing(e2a, e2b);
    if ((m1 - m0).cross(m2 - m0).dot(outward) >= 0)
      triangles.push_back({v0, v1, v2});
    else
      triangles.push_back({v0, v2, v1});
  };
  for (int k = 0; k + 1 < n[2]; ++k)
    for (int j = 0; j + 1 < n[1]; ++j)
      for (int i = 0; i + 1 < n[0]; ++i) {
        int64_t corner[8];
        int inside_count = 0;
        for (int c = 0; c < 8; ++c) {
          corner[c] = gid(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
          inside_count += value[corner[c]] < 0;
        }
        if (inside_count == 0 || inside_count == 8) continue;
        for (const auto& tet : kTets) {
          int64_t in[4], out[4];
          int ni = 0, no = 0;
          for (int c : tet) (value[corner[c]] < 0 ? in[ni++] : out[no++]) = corner[c];
          if (ni == 0 || no == 0) continue;
          Vec c_in = Vec::Zero(), c_out = Vec::Zero();
          for (int a = 0; a < ni; ++a) c_in += gpos(in[a]) / ni;
          for (int a = 0; a < no; ++a) c_out += gpos(out[a]) / no;
          Vec outward = c_out - c_in;
          if (ni == 1)
            emit(in[0], out[0], in[0], out[1], in[0], out[2], outward);
          else if (no == 1)
            emit(out[0], in[0], out[0], in[1], out[0], in[2], outward);
          else {
            // Quad (in0-out0, in0-out1, in1-out1, in1-out0), split along in0-out0 / in1-out1.
            emit(in[0], out[0], in[0], out[1], in[1], out[1], outward);
            emit(in[0], out[0], in[1], out[1], in[1], out[0], outward);
          }
        }
      }

  Mesh mesh;
  std::vector<Mesh::VertexHandle> vh;
  vh.reserve(points.size());
  for (const auto& p : points) vh.push_back(mesh.add_vertex(Mesh::Point(p.x(), p.y(), p.z())));
  for (const auto& t : triangles)
    if (!mesh.add_face(vh[t[0]], vh[t[1]], vh[t[2]]).is_valid())
      throw std::runtime_error("primitive polygonisation produced a non-manifold triangle");
  return mesh;
}

Vec gradient(const Implicit& f, const Vec& p) {
  const double e = 1e-6;
  Vec g;
  for (int a = 0; a < 3; ++a) {
    Vec d = Vec::Zero();
    d[a] = e;
    g[a] = (f(p + d) - f(p - d)) / (2 * e);
  }
  return g;
}

// Newton steps along the gradient onto f = 0; each step is bounded so that a point never jumps
// to another sheet of the surface.
Vec project_onto(const Implicit& f, Vec p, double max_step) {
  for (int it = 0; it < 30; ++it) {
    double v = f(p);
    if (std::abs(v) < 1e-12) break;
    Vec g = gradient(f, p);
    double g2 = g.squaredNorm();
    if (g2 < 1e-12) break;
    Vec step = v * g / g2;
    if (step.norm() > max_step) step *= max_step / step.norm();
    p -= step;
  }
  return p;
}

double surface_area(const Mesh& mesh) {
  double area = 0;
  for (auto fh : mesh.faces()) {
    auto it = mesh.cfv_begin(fh);
    Vec a = point(mesh, *it), b = point(mesh, *++it), c = point(mesh, *++it);
    area += triangle_area(a, b, c);
  }
  return area;
}

Mesh implicit_primitive(const ImplicitShape& s, int target_vertices) {
  // The grid only has to capture the topology (a third of the thinnest tube radius does); the
  // remeshing below refines or coarsens to the target edge length, projecting onto the surface.
  const double h = s.thinnest / 3.0;
  Mesh mesh = polygonize(s.f, s.lo, s.hi, h);
  // Remeshing keeps edges between 4/5 L and 4/3 L and ends up about 14 % denser than equilateral
  // triangles of side L (measured on these shapes), hence the factor.
  double L = std::sqrt(1.14 * surface_area(mesh) / (kAreaPerVertex * target_vertices));
  const double max_step = 0.25 * s.thinnest;
  SurfaceProjection project = [&](const Vec& p) { return project_onto(s.f, p, max_step); };
  for (auto v : mesh.vertices()) {
    Vec p = project(point(mesh, v));
    mesh.set_point(v, Mesh::Point(p.x(), p.y(), p.z()));
  }
  // The polygonisation has needles and slivers; cleaning them at the grid's own scale first keeps
  // a much finer target from splitting them into more of the same.
  if (L < h) isotropic_remesh(mesh, h, 3, project);
  isotropic_remesh(mesh, L, 6, project);
  // Remeshing lands a little off the ideal density; one correction of L fixes most of it.
  L *= std::sqrt(static_cast<double>(mesh.n_vertices()) / target_vertices);
  isotropic_remesh(mesh, L, 6, project);
  return mesh;
}

// ---------------------------------------------------------------------------------------------
// Surfaces of revolution around z, sampled exactly: a profile of (rho, z) points, each one a ring
// of vertices whose count follows its circumference, so that triangles stay near equilateral.
// A profile point with rho = 0 is a pole (one vertex); a closed profile (the torus) has none.

Mesh revolve(const std::vector<Eigen::Vector2d>& profile, bool closed, double s) {
  struct Ring {
    int first, count;  // count 1: a pole
    double offset;     // in units of the ring's angular step
  };
  std::vector<Vec> points;
  std::vector<Ring> rings;
  for (size_t k = 0; k < profile.size(); ++k) {
    double rho = profile[k].x(), z = profile[k].y();
    if (rho == 0.0) {
      rings.push_back({static_cast<int>(points.size()), 1, 0.0});
      points.emplace_back(0.0, 0.0, z);
      continue;
    }
    int count = std::max(3, static_cast<int>(std::lround(2 * M_PI * rho / s)));
    double offset = (k % 2) * 0.5;  // staggered rows give near-equilateral triangles
    rings.push_back({static_cast<int>(points.size()), count, offset});
    for (int i = 0; i < count; ++i) {
      double phi = 2 * M_PI * (i + offset) / count;
      points.emplace_back(rho * std::cos(phi), rho * std::sin(phi), z);
    }
  }
  std::vector<std::array<int, 3>> triangles;
  auto stitch = [&](const Ring& A, const Ring& B) {
    auto a = [&](int i) { return A.first + i % A.count; };
    auto b = [&](int j) { return B.first + j % B.count; };
    if (A.count == 1) {
      for (int j = 0; j < B.count; ++j) triangles.push_back({A.first, b(j + 1), b(j)});
      return;
    }
    if (B.count == 1) {
      for (int i = 0; i < A.count; ++i) triangles.push_back({a(i), a(i + 1), B.first});
      return;
    }
    // Merge the two rings by angle: always advance on the ring whose next vertex comes first.
    int i = 0, j = 0;
    while (i < A.count || j < B.count) {
      double next_a = (i + 1 + A.offset) / A.count, next_b = (j + 1 + B.offset) / B.count;
      if (j == B.count || (i < A.count && next_a <= next_b)) {
        triangles.push_back({a(i), a(i + 1), b(j)});
        ++i;
      } else {
        triangles.push_back({a(i), b(j + 1), b(j)});
        ++j;
      }
    }
  };
  for (size_t k = 0; k + 1 < rings.size(); ++k) stitch(rings[k], rings[k + 1]);
  if (closed) stitch(rings.back(), rings.front());

  // Every strip uses the same convention, so either all triangles face out or all face in.
  double volume = 0;
  for (const auto& t : triangles) volume += points[t[0]].dot(points[t[1]].cross(points[t[2]]));
  Mesh mesh;
  std::vector<Mesh::VertexHandle> vh;
  for (const auto& p : points) vh.push_back(mesh.add_vertex(Mesh::Point(p.x(), p.y(), p.z())));
  for (const auto& t : triangles) {
    auto f = volume > 0 ? mesh.add_face(vh[t[0]], vh[t[1]], vh[t[2]]) : mesh.add_face(vh[t[0]], vh[t[2]], vh[t[1]]);
    if (!f.is_valid()) throw std::runtime_error("primitive surface of revolution is not manifold");
  }
  return mesh;
}

// Row spacing of equilateral triangles with side s.
double row_spacing(double s) { return s * std::sqrt(3.0) / 2.0; }

int intervals(double length, double spacing) { return std::max(1, static_cast<int>(std::lround(length / spacing))); }

Mesh donut(double s) {
  const double R = 1.0, r = 0.4;
  int m = intervals(2 * M_PI * r, row_spacing(s));
  m += m % 2;  // even, so that the staggering alternates all the way round
  std::vector<Eigen::Vector2d> profile;
  for (int k = 0; k < m; ++k) {
    double t = 2 * M_PI * k / m;
    profile.emplace_back(R + r * std::cos(t), r * std::sin(t));
  }
  return revolve(profile, true, s);
}

Mesh cylinder(double s) {
  const double h = row_spacing(s);
  int caps = intervals(1.0, h), side = intervals(2.0, h);
  std::vector<Eigen::Vector2d> profile;
  for (int k = 0; k <= caps; ++k) profile.emplace_back(static_cast<double>(k) / caps, -1.0);
  for (int j = 1; j <= side; ++j) profile.emplace_back(1.0, -1.0 + 2.0 * j / side);
  for (int k = caps - 1; k >= 0; --k) profile.emplace_back(static_cast<double>(k) / caps, 1.0);
  return revolve(profile, false, s);
}

Mesh capsule(double s) {
  const double h = row_spacing(s);
  int caps = intervals(M_PI / 2, h), side = intervals(2.0, h);
  std::vector<Eigen::Vector2d> profile;
  profile.emplace_back(0.0, -2.0);
  for (int k = 1; k <= caps; ++k) {
    double theta = -M_PI / 2 + (M_PI / 2) * k / caps;
    profile.emplace_back(std::cos(theta), -1.0 + std::sin(theta));
  }
  for (int j = 1; j <= side; ++j) profile.emplace_back(1.0, -1.0 + 2.0 * j / side);
  for (int k = 1; k < caps; ++k) {
    double theta = (M_PI / 2) * k / caps;
    profile.emplace_back(std::cos(theta), 1.0 + std::sin(theta));
  }
  profile.emplace_back(0.0, 2.0);
  return revolve(profile, false, s);
}

// Chooses the sampling step whose vertex count is closest to the target.
Mesh revolved_primitive(const std::function<Mesh(double)>& build, double area, int target_vertices) {
  double s = std::sqrt(area / (kAreaPerVertex * target_vertices));
  Mesh best;
  long best_error = -1;
  for (int it = 0; it < 8; ++it) {
    Mesh m = build(s);
    long error = std::labs(static_cast<long>(m.n_vertices()) - target_vertices);
    if (best_error < 0 || error < best_error) {
      best = m;
      best_error = error;
    }
    if (error * 100 <= target_vertices) break;
    s *= std::sqrt(static_cast<double>(m.n_vertices()) / target_vertices);
  }
  return best;
}

struct Entry {
  const char* name;
  int default_vertices;
};
const Entry kEntries[] = {{"ypsilon", 480},         {"bottle", 1530},   {"donut", 1728},  {"triple-torus", 2256},
                          {"crossed-cylinders", 3660}, {"cylinder", 1200}, {"capsule", 1200}, {"two-tunnels", 4000},
                          {"mushroom", 3000}};

}  // namespace

std::vector<std::string> primitive_names() {
  std::vector<std::string> names;
  for (const auto& e : kEntries) names.emplace_back(e.name);
  return names;
}

Mesh make_primitive(const std::string& name, int resolution) {
  const Entry* entry = nullptr;
  for (const auto& e : kEntries)
    if (name == e.name) entry = &e;
  if (!entry) {
    std::string list;
    for (const auto& n : primitive_names()) list += (list.empty() ? "" : ", ") + n;
    throw InputError("unknown primitive '" + name + "'; valid names: " + list);
  }
  if (resolution != 0 && (resolution < 200 || resolution > 1000000))
    throw InputError("primitive resolution " + std::to_string(resolution) +
                     " is out of range: give an approximate vertex count in [200, 1000000], or 0 for the default");
  const int target = resolution == 0 ? entry->default_vertices : resolution;
  const std::string n = entry->name;
  if (n == "ypsilon") return implicit_primitive(ypsilon_shape(), target);
  if (n == "bottle") return implicit_primitive(bottle_shape(), target);
  if (n == "triple-torus") return implicit_primitive(triple_torus_shape(), target);
  if (n == "crossed-cylinders") return implicit_primitive(crossed_cylinders_shape(), target);
  if (n == "two-tunnels") return implicit_primitive(two_tunnels_shape(), target);
  if (n == "mushroom") return implicit_primitive(mushroom_shape(), target);
  if (n == "donut") return revolved_primitive(donut, 4 * M_PI * M_PI * 1.0 * 0.4, target);
  if (n == "cylinder") return revolved_primitive(cylinder, 2 * M_PI * 2.0 + 2 * M_PI, target);
  return revolved_primitive(capsule, 2 * M_PI * 2.0 + 4 * M_PI, target);
}

}  // namespace sdm
