#pragma once
// Synthetic meshes with known skeletons for the layout tests: surfaces of revolution around z
// (capsules, tubes), unions of such tubes (a Y), and a torus with a ring of nodes; and the
// deformations the transfer tests put them through (a new tessellation, a bent arm).
#include "libstm/mesh/isotropic_remesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/skeleton.h"
#include "libstm/geometry/triangle_bvh.h"

#include <Eigen/Geometry>

#include <cmath>
#include <functional>
#include <vector>

namespace synth {

using Vec3 = Eigen::Vector3d;

// Adds a closed surface of revolution around z: `profile` lists (z, rho) from the south pole
// (rho = 0) to the north pole (rho = 0); `n` vertices per ring, ring k turned by k * twist radians.
// `deform` maps each point (e.g. a radial bump, a rotation). Returns the first vertex index.
inline int add_revolution(sdm::Mesh& m, const std::vector<std::pair<double, double>>& profile, int n, double twist,
                          const std::function<Vec3(const Vec3&)>& deform) {
  const int first = int(m.n_vertices());
  const int rings = int(profile.size()) - 2;
  auto add = [&](const Vec3& p) {
    const Vec3 q = deform ? deform(p) : p;
    return m.add_vertex(sdm::Mesh::Point(q.x(), q.y(), q.z()));
  };
  auto south = add({0, 0, profile.front().first});
  std::vector<std::vector<sdm::Mesh::VertexHandle>> ring(rings);
  for (int k = 0; k < rings; ++k)
    for (int i = 0; i < n; ++i) {
      const double a = 2 * M_PI * i / n + k * twist;
      ring[k].push_back(add({profile[k + 1].second * std::cos(a), profile[k + 1].second * std::sin(a), profile[k + 1].first}));
    }
  auto north = add({0, 0, profile.back().first});
  for (int i = 0; i < n; ++i) m.add_face(south, ring[0][(i + 1) % n], ring[0][i]);
  for (int k = 0; k + 1 < rings; ++k)
    for (int i = 0; i < n; ++i) {
      const int j = (i + 1) % n;
      m.add_face(ring[k][i], ring[k][j], ring[k + 1][j]);
      m.add_face(ring[k][i], ring[k + 1][j], ring[k + 1][i]);
    }
  for (int i = 0; i < n; ++i) m.add_face(north, ring[rings - 1][i], ring[rings - 1][(i + 1) % n]);
  return first;
}

// Capsule profile: hemisphere of radius r below z = 0, cylinder up to z = len, hemisphere above.
inline std::vector<std::pair<double, double>> capsule_profile(double r, double len, int cap_rings, int side_rings) {
  std::vector<std::pair<double, double>> p;
  p.push_back({-r, 0});
  for (int k = 1; k <= cap_rings; ++k) {
    const double lat = -M_PI / 2 + (M_PI / 2) * k / cap_rings;  // up to the equator
    p.push_back({r * std::sin(lat), r * std::cos(lat)});
  }
  for (int k = 1; k < side_rings; ++k) p.push_back({len * k / side_rings, r});
  for (int k = 0; k < cap_rings; ++k) {
    const double lat = (M_PI / 2) * k / cap_rings;
    p.push_back({len + r * std::sin(lat), r * std::cos(lat)});
  }
  p.push_back({len + r, 0});
  return p;
}

// Straight chain of `nodes` skeleton nodes from a to b; vertices [first, last) go to the node
// nearest by axial parameter.
inline void add_chain(sdm::Skeleton& s, const sdm::Mesh& m, int first, int last, const Vec3& a, const Vec3& b, int nodes,
                      int shared_first_node = -1) {
  const int base = int(s.nodes.size());
  std::vector<int> ids;
  for (int k = 0; k < nodes; ++k) {
    if (k == 0 && shared_first_node >= 0) {
      ids.push_back(shared_first_node);
      continue;
    }
    s.nodes.push_back(a + (b - a) * (double(k) / (nodes - 1)));
    ids.push_back(int(s.nodes.size()) - 1);
  }
  (void)base;
  for (int k = 0; k + 1 < nodes; ++k) s.edges.push_back({ids[k], ids[k + 1]});
  s.vertex_node.resize(m.n_vertices(), 0);
  const Vec3 ab = b - a;
  for (int v = first; v < last; ++v) {
    const Vec3 p = sdm::point(m, m.vertex_handle(v));
    const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    s.vertex_node[v] = ids[int(std::lround(t * (nodes - 1)))];
  }
}

struct Shape {
  sdm::Mesh mesh;
  sdm::Skeleton skeleton;
};

// A capsule along z (axis from 0 to len) with `nodes` chain nodes; `bump` > 0 makes the section
// lopsided towards +x (an asymmetric, non-round cross-section with a well defined direction).
inline Shape capsule(double r, double len, int nodes, int n_around = 48, int cap_rings = 8, int side_rings = 24,
                     double twist = 0, double bump = 0) {
  Shape s;
  auto deform = [&](const Vec3& p) {
    if (bump == 0) return p;
    const double phi = std::atan2(p.y(), p.x());
    const double f = 1 + bump * (0.6 * std::cos(2 * phi) + 0.4 * std::cos(phi));
    return Vec3(p.x() * f, p.y() * f, p.z());
  };
  add_revolution(s.mesh, capsule_profile(r, len, cap_rings, side_rings), n_around, twist, deform);
  add_chain(s.skeleton, s.mesh, 0, int(s.mesh.n_vertices()), {0, 0, 0}, {0, 0, len}, nodes);
  return s;
}

// Rotation taking +z to `dir`.
inline Eigen::Matrix3d rotation_to(const Vec3& dir) {
  return Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), dir.normalized()).toRotationMatrix();
}

// A Y: three lopsided capsules leaving a junction at the origin in the xy plane, of different
// lengths, each a chain of nodes sharing the junction node 0.
inline Shape ypsilon(int n_around = 40, int side_rings = 20, double twist = 0) {
  Shape s;
  s.skeleton.nodes.push_back({0, 0, 0});
  const double lens[3] = {3.0, 2.2, 1.6};
  const double angles[3] = {M_PI / 2, M_PI / 2 + 2.2, M_PI / 2 - 2.0};
  for (int k = 0; k < 3; ++k) {
    const Vec3 dir(std::cos(angles[k]), std::sin(angles[k]), 0);
    const Eigen::Matrix3d R = rotation_to(dir);
    auto deform = [&](const Vec3& p) {
      const double phi = std::atan2(p.y(), p.x());
      const double f = 1 + 0.2 * (0.6 * std::cos(2 * phi) + 0.4 * std::cos(phi));
      return Vec3(R * Vec3(p.x() * f, p.y() * f, p.z()));
    };
    const int first = add_revolution(s.mesh, capsule_profile(0.45, lens[k], 6, side_rings), n_around, twist, deform);
    add_chain(s.skeleton, s.mesh, first, int(s.mesh.n_vertices()), {0, 0, 0}, dir * lens[k], 3 + k, 0);
  }
  return s;
}

// A torus around z: major radius R, minor radius r, `segs` skeleton nodes on the ring.
inline Shape torus(double R, double r, int segs, int n_major = 96, int n_minor = 24) {
  Shape s;
  std::vector<sdm::Mesh::VertexHandle> vh;
  for (int i = 0; i < n_major; ++i)
    for (int j = 0; j < n_minor; ++j) {
      const double a = 2 * M_PI * i / n_major, b = 2 * M_PI * j / n_minor;
      vh.push_back(s.mesh.add_vertex(
          sdm::Mesh::Point((R + r * std::cos(b)) * std::cos(a), (R + r * std::cos(b)) * std::sin(a), r * std::sin(b))));
    }
  auto id = [&](int i, int j) { return vh[(i % n_major) * n_minor + (j % n_minor)]; };
  for (int i = 0; i < n_major; ++i)
    for (int j = 0; j < n_minor; ++j) {
      s.mesh.add_face(id(i, j), id(i + 1, j), id(i + 1, j + 1));
      s.mesh.add_face(id(i, j), id(i + 1, j + 1), id(i, j + 1));
    }
  for (int k = 0; k < segs; ++k) {
    const double a = 2 * M_PI * k / segs;
    s.skeleton.nodes.push_back({R * std::cos(a), R * std::sin(a), 0});
    s.skeleton.edges.push_back({k, (k + 1) % segs});
  }
  for (auto v : s.mesh.vertices()) {
    const Vec3 p = sdm::point(s.mesh, v);
    double a = std::atan2(p.y(), p.x());
    if (a < 0) a += 2 * M_PI;
    s.skeleton.vertex_node.push_back(int(std::lround(a / (2 * M_PI) * segs)) % segs);
  }
  return s;
}

// The same shape moved rigidly: mesh points and skeleton nodes.
inline Shape transformed(const Shape& in, const Eigen::Matrix3d& R, const Vec3& t) {
  Shape s = in;
  for (auto v : s.mesh.vertices()) {
    const Vec3 p = R * sdm::point(s.mesh, v) + t;
    s.mesh.set_point(v, sdm::Mesh::Point(p.x(), p.y(), p.z()));
  }
  for (auto& n : s.skeleton.nodes) n = R * n + t;
  return s;
}

inline double mean_edge(const sdm::Mesh& m) {
  double s = 0;
  for (auto e : m.edges()) s += m.calc_edge_length(e);
  return s / double(m.n_edges());
}

// A copy of `mesh` with another tessellation (mean edge times edge_factor), its vertices on the
// original surface; without uv.
inline sdm::Mesh remeshed(const sdm::Mesh& mesh, double edge_factor) {
  const sdm::TriangleBvh bvh(sdm::vertex_matrix(mesh), sdm::face_matrix(mesh));
  sdm::Mesh copy = mesh;
  copy.release_halfedge_texcoords2D();
  sdm::isotropic_remesh(copy, edge_factor * mean_edge(mesh), 4, [&](const Eigen::Vector3d& p) { return bvh.closest_point(p).point; });
  return copy;
}

// The right arm of the ypsilon primitive (primitives.cpp): from the origin towards (0.78, 0.78, 0).
inline const Vec3 kYpsilonArm = Vec3(1, 1, 0).normalized();

// The ypsilon's right arm bent by `degrees` out of the Y's plane towards +z (progressively, from 0.3
// along the arm on) and thickened by `thicken` (radially, same ramp). Out of the plane, so that the
// bent Y is not an in-plane Y with its arms relabelled: bent within the plane towards the stem, the
// Y's angles fit a match with stem and left arm exchanged better than the true one.
inline Vec3 bend_ypsilon_arm(const Vec3& p, double degrees, double thicken) {
  const Vec3 pivot = 0.3 * kYpsilonArm;
  const double s = (p - pivot).dot(kYpsilonArm);
  if (s <= 0) return p;
  const double w = std::min(1.0, s / 0.4);
  const Vec3 radial = (p - pivot) - s * kYpsilonArm;
  const Vec3 q = s * kYpsilonArm + (1 + thicken * w) * radial;
  const Vec3 across = Vec3::UnitZ().cross(kYpsilonArm);  // in the plane, across the arm
  return pivot + Eigen::AngleAxisd(-degrees * M_PI / 180 * w, across).toRotationMatrix() * q;
}

// Every vertex moved by `move`.
inline sdm::Mesh moved(sdm::Mesh m, const std::function<Vec3(const Vec3&)>& move) {
  for (auto v : m.vertices()) {
    const Vec3 q = move(sdm::point(m, v));
    m.set_point(v, sdm::Mesh::Point(q.x(), q.y(), q.z()));
  }
  return m;
}

}  // namespace synth
