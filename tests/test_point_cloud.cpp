// Point clouds (libstm/mesh/point_cloud.h, libstm/skeleton/point_skeleton.h): each reader, normals
// read and estimated, the refusals, and skeletons of sampled shapes with known axes.
#include "libstm/core/errors.h"
#include "libstm/mesh/point_cloud.h"
#include "libstm/skeleton/point_skeleton.h"
#include "tests/test_util.h"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>

namespace {

using Vec3 = Eigen::Vector3d;

// Points uniform on a capsule around z: radius r, cylinder from z = 0 to len, hemispherical caps;
// with each point's outward normal.
void sample_capsule(int n, double r, double len, std::vector<Vec3>& p, std::vector<Vec3>& nrm, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const double side = 2 * M_PI * r * len, caps = 4 * M_PI * r * r;
  for (int i = 0; i < n; ++i) {
    if (u(rng) * (side + caps) < side) {
      const double a = 2 * M_PI * u(rng), z = len * u(rng);
      nrm.emplace_back(std::cos(a), std::sin(a), 0);
      p.emplace_back(r * std::cos(a), r * std::sin(a), z);
    } else {
      Vec3 d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
      while (d.norm() < 1e-3 || d.norm() > 0.5) d = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
      d.normalize();
      nrm.push_back(d);
      p.push_back(r * d + Vec3(0, 0, d.z() > 0 ? len : 0));
    }
  }
}

// Points uniform in angle on a torus around z (major radius R, minor r).
std::vector<Vec3> sample_torus(int n, double R, double r, unsigned seed = 11) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 2 * M_PI);
  std::vector<Vec3> p;
  for (int i = 0; i < n; ++i) {
    const double a = u(rng), b = u(rng);
    p.emplace_back((R + r * std::cos(b)) * std::cos(a), (R + r * std::cos(b)) * std::sin(a), r * std::sin(b));
  }
  return p;
}

// Points uniform by area on a torus around z (major radius R, minor r), as a scan samples it:
// the outer side, farther from the axis, takes more of them.
std::vector<Vec3> sample_torus_by_area(int n, double R, double r, unsigned seed = 13) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> p;
  while (int(p.size()) < n) {
    const double a = 2 * M_PI * u(rng), b = 2 * M_PI * u(rng);
    if (u(rng) * (R + r) >= R + r * std::cos(b)) continue;
    p.emplace_back((R + r * std::cos(b)) * std::cos(a), (R + r * std::cos(b)) * std::sin(a), r * std::sin(b));
  }
  return p;
}

std::string xyz_text(const std::vector<Vec3>& p, const std::vector<Vec3>* n = nullptr) {
  std::string s;
  char line[256];
  for (size_t i = 0; i < p.size(); ++i) {
    if (n) std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.9g %.9g %.9g\n", p[i].x(), p[i].y(), p[i].z(), (*n)[i].x(), (*n)[i].y(), (*n)[i].z());
    else std::snprintf(line, sizeof line, "%.17g %.17g %.17g\n", p[i].x(), p[i].y(), p[i].z());
    s += line;
  }
  return s;
}

template <class T>
void put(std::string& s, T x) {
  s.append(reinterpret_cast<const char*>(&x), sizeof x);
}

double max_gap(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  REQUIRE(a.size() == b.size());
  double m = 0;
  for (size_t i = 0; i < a.size(); ++i) m = std::max(m, (a[i] - b[i]).norm());
  return m;
}

}  // namespace

TEST_CASE("point clouds: every reader gives the points, normals and colours of its file", "[point_cloud]") {
  test_util::TempDir dir;
  std::vector<Vec3> p, n;
  sample_capsule(300, 0.5, 2.0, p, n);
  SECTION(".xyz with and without normals") {
    test_util::write_file(dir / "a.xyz", "# a comment\n" + xyz_text(p));
    test_util::write_file(dir / "b.xyz", xyz_text(p, &n));
    const sdm::PointCloud a = sdm::read_point_cloud(dir / "a.xyz"), b = sdm::read_point_cloud(dir / "b.xyz");
    CHECK(max_gap(a.points, p) == 0.0);
    CHECK(a.normals.empty());
    CHECK(max_gap(b.normals, n) < 1e-8);
    CHECK(sdm::is_point_cloud_file(dir / "a.xyz"));
  }
  SECTION("ASCII PLY with normals and colours; binary PLY of floats") {
    std::string ascii = "ply\nformat ascii 1.0\nelement vertex " + std::to_string(p.size()) +
                        "\nproperty double x\nproperty double y\nproperty double z\nproperty float nx\nproperty float ny\n"
                        "property float nz\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face 0\n"
                        "property list uchar int vertex_indices\nend_header\n";
    char line[256];
    for (size_t i = 0; i < p.size(); ++i) {
      std::snprintf(line, sizeof line, "%.17g %.17g %.17g %.9g %.9g %.9g 255 0 51\n", p[i].x(), p[i].y(), p[i].z(), n[i].x(), n[i].y(), n[i].z());
      ascii += line;
    }
    test_util::write_file(dir / "a.ply", ascii);
    std::string bin = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(p.size()) +
                      "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    for (const Vec3& q : p) put(bin, float(q.x())), put(bin, float(q.y())), put(bin, float(q.z()));
    test_util::write_file(dir / "b.ply", bin);
    REQUIRE(sdm::is_point_cloud_file(dir / "a.ply"));
    REQUIRE(sdm::is_point_cloud_file(dir / "b.ply"));
    const sdm::PointCloud a = sdm::read_point_cloud(dir / "a.ply"), b = sdm::read_point_cloud(dir / "b.ply");
    CHECK(max_gap(a.points, p) == 0.0);
    CHECK(max_gap(a.normals, n) < 1e-8);
    REQUIRE(a.colors.size() == p.size());
    CHECK(a.colors[5].x() == 1.0f);
    CHECK(a.colors[5].z() == Approx(0.2f));
    CHECK(max_gap(b.points, p) < 1e-6);
    CHECK(b.normals.empty());
  }
  SECTION("OFF and NOFF with zero faces") {
    std::string off = "OFF\n" + std::to_string(p.size()) + " 0 0\n" + xyz_text(p);
    std::string noff = "NOFF\n" + std::to_string(p.size()) + " 0 0\n" + xyz_text(p, &n);
    test_util::write_file(dir / "a.off", off);
    test_util::write_file(dir / "b.off", noff);
    test_util::write_file(dir / "mesh.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
    CHECK(sdm::is_point_cloud_file(dir / "a.off"));
    CHECK_FALSE(sdm::is_point_cloud_file(dir / "mesh.off"));
    CHECK(max_gap(sdm::read_point_cloud(dir / "a.off").points, p) == 0.0);
    CHECK(max_gap(sdm::read_point_cloud(dir / "b.off").normals, n) < 1e-8);
  }
  SECTION("PCD ascii with normals and missing returns; binary; binary_compressed refused") {
    std::string head = "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z normal_x normal_y normal_z\nSIZE 8 8 8 4 4 4\nTYPE F F F F F F\n"
                       "COUNT 1 1 1 1 1 1\nWIDTH " + std::to_string(p.size() + 1) + "\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS " +
                       std::to_string(p.size() + 1) + "\nDATA ascii\n";
    test_util::write_file(dir / "a.pcd", head + "nan nan nan 0 0 1\n" + xyz_text(p, &n));
    const sdm::PointCloud a = sdm::read_point_cloud(dir / "a.pcd");
    CHECK(a.no_returns == 1);
    CHECK(max_gap(a.points, p) == 0.0);
    CHECK(max_gap(a.normals, n) < 1e-8);
    std::string bin = "VERSION 0.7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\nWIDTH " + std::to_string(p.size()) +
                      "\nHEIGHT 1\nPOINTS " + std::to_string(p.size()) + "\nDATA binary\n";
    for (const Vec3& q : p) put(bin, float(q.x())), put(bin, float(q.y())), put(bin, float(q.z())), put(bin, uint32_t(0x00FF0000));
    test_util::write_file(dir / "b.pcd", bin);
    const sdm::PointCloud b = sdm::read_point_cloud(dir / "b.pcd");
    CHECK(max_gap(b.points, p) < 1e-6);
    REQUIRE(b.colors.size() == p.size());
    CHECK(b.colors[0] == Eigen::Vector3f(1, 0, 0));
    std::string packed = bin;
    packed.replace(packed.find("DATA binary"), 11, "DATA binary_compressed");
    test_util::write_file(dir / "c.pcd", packed);
    CHECK_THROWS_WITH(sdm::read_point_cloud(dir / "c.pcd"), Catch::Contains("binary_compressed"));
  }
}

TEST_CASE("point clouds: malformed files are refused naming the line, the point or the count", "[point_cloud]") {
  test_util::TempDir dir;
  test_util::write_file(dir / "nan.xyz", "0 0 0\n1 0 0\nnan 1 0\n");
  CHECK_THROWS_WITH(sdm::read_point_cloud(dir / "nan.xyz"), Catch::Contains("line 3") && Catch::Contains("NaN"));
  test_util::write_file(dir / "inf.xyz", "0 0 0\n1 0 inf\n");
  CHECK_THROWS_WITH(sdm::read_point_cloud(dir / "inf.xyz"), Catch::Contains("line 2"));
  test_util::write_file(dir / "cols.xyz", "0 0 0\n1 0 0 5\n");
  CHECK_THROWS_WITH(sdm::read_point_cloud(dir / "cols.xyz"), Catch::Contains("line 2 has 4 values"));
  // A header counting a billion vertices over a few bytes: refused before anything is allocated.
  test_util::write_file(dir / "big.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\nproperty float x\n"
                                         "property float y\nproperty float z\nend_header\n0123456789ab");
  CHECK_THROWS_WITH(sdm::read_point_cloud(dir / "big.ply"), Catch::Contains("1000000000 vertices"));
  test_util::write_file(dir / "short.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nPOINTS 3\nDATA ascii\n0 0 0\n1 1 1\n");
  CHECK_THROWS_WITH(sdm::read_point_cloud(dir / "short.pcd"), Catch::Contains("2 of the 3 points"));
}

TEST_CASE("point clouds: duplicates merged and counted; too few, flat and linear clouds refused", "[point_cloud]") {
  std::vector<Vec3> p, n;
  sample_capsule(400, 0.5, 2.0, p, n);
  sdm::PointCloud c;
  c.points = p;
  c.points.insert(c.points.end(), p.begin(), p.begin() + 25);
  std::vector<int> index_of;
  const sdm::CloudReport r = sdm::prepare_cloud(c, "cloud", &index_of);
  CHECK(r.points_read == 425);
  CHECK(r.duplicates == 25);
  CHECK(r.points == 400);
  CHECK(index_of[410] == 10);
  CHECK(r.mean_spacing > 0);
  CHECK(r.extents[0] > r.extents[2]);

  sdm::PointCloud few;
  few.points.assign(p.begin(), p.begin() + 150);
  CHECK_THROWS_WITH(sdm::prepare_cloud(few, "few"), Catch::Contains("150 distinct points") && Catch::Contains("at least 200"));
  sdm::PointCloud flat, line;
  for (int i = 0; i < 500; ++i) {
    flat.points.emplace_back(i % 25, i / 25, 0.0);
    line.points.emplace_back(i, 2.0 * i, -i + 1e-9 * (i % 3));
  }
  CHECK_THROWS_WITH(sdm::prepare_cloud(flat, "flat"), Catch::Contains("lie on a plane"));
  CHECK_THROWS_WITH(sdm::prepare_cloud(line, "line"), Catch::Contains("lie on a line"));
}

TEST_CASE("point clouds: estimated normals are the surface's, turned outward", "[point_cloud]") {
  std::vector<Vec3> p, n;
  sample_capsule(3000, 0.5, 2.0, p, n);
  const std::vector<Vec3> est = sdm::estimate_normals(p);
  int agree = 0;
  for (size_t i = 0; i < p.size(); ++i) agree += est[i].dot(n[i]) > 0.9;
  CHECK(agree >= int(0.97 * double(p.size())));
  for (const Vec3& e : est) CHECK(std::abs(e.norm() - 1) < 1e-9);
}

TEST_CASE("point clouds: a capsule's skeleton is one branch at its radius", "[point_cloud]") {
  const double R = 0.5, len = 3.0;
  std::vector<Vec3> p, n;
  sample_capsule(6000, R, len, p, n);
  sdm::PointSkeletonStats st;
  const sdm::Skeleton s = sdm::point_cloud_skeleton(p, {}, nullptr, &st);
  INFO(s.nodes.size() << " nodes, area ratio " << st.area_ratio);
  CHECK(s.components() == 1);
  CHECK(s.end_nodes() == 2);
  CHECK(s.branch_nodes() == 0);
  CHECK(s.cycles() == 0);
  REQUIRE(s.vertex_node.size() == p.size());
  const std::vector<double> radii = sdm::node_radii(s, p);
  int measured = 0;
  double off_axis = 0;
  for (size_t a = 0; a < s.nodes.size(); ++a) {
    const Vec3& q = s.nodes[a];
    if (q.z() < 0.5 || q.z() > len - 0.5) continue;  // the cylinder, away from the caps
    ++measured;
    // Each node is the centre of about 200 random points around the axis: off it by about
    // R / sqrt(2 * 200) per coordinate (0.06 R on average).
    CHECK(std::hypot(q.x(), q.y()) < 0.2 * R);
    off_axis += std::hypot(q.x(), q.y());
    CHECK(std::abs(radii[a] - R) < 0.03 * R);          // at the radius
  }
  REQUIRE(measured >= 5);
  CHECK(off_axis / measured < 0.1 * R);
}

TEST_CASE("point clouds: a torus's skeleton is one cycle around its hole", "[point_cloud]") {
  const double R = 1.0, r = 0.3;
  const std::vector<Vec3> p = sample_torus(8000, R, r);
  const sdm::Skeleton s = sdm::point_cloud_skeleton(p);
  CHECK(s.components() == 1);
  CHECK(s.cycles() == 1);
  CHECK(s.end_nodes() == 0);
  const std::vector<double> radii = sdm::node_radii(s, p);
  for (size_t a = 0; a < s.nodes.size(); ++a) {
    CHECK(std::abs(std::hypot(s.nodes[a].x(), s.nodes[a].y()) - R) < 0.05 * R);
    CHECK(std::abs(radii[a] - r) < 0.05 * r);
  }
}

TEST_CASE("point clouds: a torus whose hole is narrower than its tube keeps its cycle", "[point_cloud]") {
  // Hole radius R - r = 0.6 r. The contraction draws the fat ring towards its hole (its contracted
  // cycle is shorter than 2 pi r), but the centroids of its nodes' points lie on a circle of about
  // R + r^2 / 2R = 1.9 r (points uniform by area), wider than the 1.5 r at which the hole closes,
  // and the disc of that circle crosses the hole's wall.
  const double R = 1.6, r = 1.0;
  const std::vector<Vec3> p = sample_torus_by_area(8000, R, r);
  const sdm::Skeleton s = sdm::point_cloud_skeleton(p);
  CHECK(s.components() == 1);
  CHECK(s.cycles() == 1);
  CHECK(s.end_nodes() == 0);
  // The cycle goes around the hole: every node (the centre of its points, an arc of the ring)
  // lies beyond the hole's wall and within the tube's outer side.
  for (const Vec3& q : s.nodes) {
    const double rho = std::hypot(q.x(), q.y());
    CHECK(rho > R - r);
    CHECK(rho < R + r);
  }
}

TEST_CASE("point clouds: sdm skeleton and info take a cloud, the mesh commands name it", "[point_cloud]") {
  test_util::TempDir dir;
  std::vector<Vec3> p, n;
  sample_capsule(2000, 0.5, 3.0, p, n);
  std::string text = xyz_text(p) + xyz_text({p[0], p[1], p[2]});
  test_util::write_file(dir / "c.xyz", text);
  auto r = test_util::run_sdm("skeleton " + dir / "c.xyz" + " -o " + dir / "s.json --json");
  REQUIRE(r.exit_code == 0);
  const auto j = test_util::last_json(r);
  CHECK(j["end_nodes"] == 2);
  CHECK(j["duplicates_merged"] == 3);
  CHECK(std::abs(j["mean_node_radius"].get<double>() - 0.5) < 0.05);
  r = test_util::run_sdm("info " + dir / "c.xyz" + " --json");
  REQUIRE(r.exit_code == 0);
  const auto i = nlohmann::json::parse(r.output);
  CHECK(i["points"] == 2000);
  CHECK(i["points_read"] == 2003);
  CHECK(i["normals"] == "estimated");
  r = test_util::run_sdm("remesh " + dir / "c.xyz" + " -o " + dir / "m.obj");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("is a point cloud") != std::string::npos);
  test_util::write_file(dir / "few.xyz", xyz_text({p.begin(), p.begin() + 50}));
  r = test_util::run_sdm("skeleton " + dir / "few.xyz" + " -o " + dir / "f.json");
  CHECK(r.exit_code == 2);
  CHECK(r.output.find("at least 200") != std::string::npos);
}

TEST_CASE("point clouds: the LIDAR street lamp of ../shared is a tree of its pole, arm and cross-bar", "[point_cloud]") {
  const std::string path = std::string(SDM_TEST_DATA) + "/../../../shared/models/pointclouds/lamppost.pcd";
  if (!std::ifstream(path).good()) {
    WARN("no " << path << ": skipped");
    return;
  }
  sdm::CloudReport report;
  const sdm::PointCloud c = sdm::load_point_cloud(path, &report);
  CHECK(report.points_read == 1771);
  CHECK(report.points + report.duplicates == 1771);
  const sdm::Skeleton s = sdm::point_cloud_skeleton(c.points);
  CHECK(s.components() == 1);
  CHECK(s.cycles() == 0);
  CHECK(s.end_nodes() >= 3);  // the pole's foot, the arm's lamp, the cross-bar's two ends
  CHECK(s.vertex_node.size() == c.points.size());
}
