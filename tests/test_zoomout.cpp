// The Laplace-Beltrami eigenbasis (libstm/geometry/laplace_basis) and the spectral refinement of
// a correspondence (libstm/registration/zoomout).
#include "faust_pairs.h"
#include "synthetic_shapes.h"
#include "test_util.h"

#include "libstm/core/errors.h"
#include "libstm/core/stopwatch.h"
#include "libstm/geometry/laplace_basis.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/primitives.h"
#include "libstm/registration/correspondence_error.h"
#include "libstm/registration/zoomout.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <numeric>
#include <random>
#include <sstream>

namespace {

// An icosahedron subdivided `levels` times, its vertices on the sphere of radius r.
void icosphere(double r, int levels, std::vector<Eigen::Vector3d>& points, std::vector<std::array<int, 3>>& triangles) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  points = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
            {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  triangles = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
               {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> middle;
    auto mid = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto it = middle.find(key);
      if (it != middle.end()) return it->second;
      points.push_back((points[size_t(a)] + points[size_t(b)]) / 2);
      return middle[key] = int(points.size()) - 1;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& t : triangles) {
      const int ab = mid(t[0], t[1]), bc = mid(t[1], t[2]), ca = mid(t[2], t[0]);
      finer.push_back({t[0], ab, ca}), finer.push_back({t[1], bc, ab}), finer.push_back({t[2], ca, bc}), finer.push_back({ab, bc, ca});
    }
    triangles = finer;
  }
  for (auto& p : points) p = r * p.normalized();
}

// p (on or near face f of `m`) as a source point: f and p's barycentric coordinates in fv_range order.
sdm::SourcePoint on_face(const sdm::Mesh& m, int f, const Eigen::Vector3d& p) {
  Eigen::Vector3d c[3];
  int k = 0;
  for (auto v : m.fv_range(m.face_handle(f))) c[k++] = sdm::point(m, v);
  return {f, sdm::barycentric(p, c[0], c[1], c[2])};
}

std::vector<int> identity(size_t n) {
  std::vector<int> v(n);
  std::iota(v.begin(), v.end(), 0);
  return v;
}

// Mean and 90th percentile of the straight distances between each entry's source point and `truth`'s,
// in % of the source's bounding-box diagonal.
std::pair<double, double> euclidean_error(const sdm::Mesh& source, const std::vector<sdm::SourcePoint>& map,
                                          const std::vector<sdm::SourcePoint>& truth) {
  std::vector<double> d;
  for (size_t i = 0; i < map.size(); ++i) d.push_back((sdm::position_of(source, map[i]) - sdm::position_of(source, truth[i])).norm());
  const double diag = sdm::bounding_box_diagonal(source);
  const double mean = std::accumulate(d.begin(), d.end(), 0.0) / double(d.size());
  std::sort(d.begin(), d.end());
  return {100 * mean / diag, 100 * d[d.size() * 9 / 10] / diag};
}

}  // namespace

TEST_CASE("laplace_basis: a sphere's eigenvalues are l (l + 1) / R^2, 1, 3 and 5 times", "[zoomout]") {
  std::vector<Eigen::Vector3d> points;
  std::vector<std::array<int, 3>> triangles;
  const double R = 2;
  icosphere(R, 4, points, triangles);  // 2562 vertices
  const sdm::LaplaceBasis b = sdm::laplace_basis(points, triangles, 16);
  REQUIRE(b.values.size() == 16);
  CHECK(std::abs(b.values[0]) < 1e-8);
  CHECK(b.mass.sum() == Approx(4 * M_PI * R * R).epsilon(0.01));
  for (int i = 1; i < 16; ++i) {
    const int l = i < 4 ? 1 : i < 9 ? 2 : 3;
    INFO("eigenvalue " << i << ": " << b.values[i] << ", expected " << l * (l + 1) / (R * R));
    CHECK(b.values[i] == Approx(l * (l + 1) / (R * R)).epsilon(0.02));
  }
  // M-orthonormal.
  const Eigen::MatrixXd gram = b.vectors.transpose() * b.mass.asDiagonal() * b.vectors;
  CHECK((gram - Eigen::MatrixXd::Identity(16, 16)).cwiseAbs().maxCoeff() < 1e-6);
  CHECK_THROWS_AS(sdm::laplace_basis(points, triangles, 0), sdm::InputError);
  CHECK_THROWS_AS(sdm::laplace_basis(points, triangles, int(points.size())), sdm::InputError);
}

TEST_CASE("zoomout: a noisy map of the bottle onto its turned remesh comes back near the truth", "[zoomout]") {
  const sdm::Mesh source = sdm::make_primitive("bottle");
  sdm::Mesh target = synth::remeshed(source, 1.2);
  // The truth: each target vertex's closest source point, then the target turned.
  const sdm::TriangleBvh bvh(sdm::vertex_matrix(source), sdm::face_matrix(source));
  std::vector<sdm::SourcePoint> truth, start;
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0, 0.03 * sdm::bounding_box_diagonal(source) / std::sqrt(3.0));
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (auto v : target.vertices()) {
    const Eigen::Vector3d p = sdm::point(target, v);
    const auto c = bvh.closest_point(p);
    truth.push_back(on_face(source, c.face, c.point));
    // The start: the source point closest to the true one moved by 3 % of the diagonal at random.
    const auto n = bvh.closest_point(c.point + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
    start.push_back(on_face(source, n.face, n.point));
  }
  for (auto v : target.vertices()) {
    const Eigen::Vector3d p = turn * sdm::point(target, v);
    target.set_point(v, sdm::Mesh::Point(p.x(), p.y(), p.z()));
  }
  const auto [mean0, p90_0] = euclidean_error(source, start, truth);
  sdm::ZoomOutOptions o;  // plain ZoomOut first: spectral alone, every source vertex, one way
  o.k_start = 10, o.k_end = 60, o.step = 5, o.window = 0, o.spatial_weight = 0, o.bidirectional = false;
  const std::vector<sdm::SourcePoint> refined = sdm::refine_correspondence(source, target, start, o);
  const auto [mean1, p90_1] = euclidean_error(source, refined, truth);
  INFO("mean " << mean0 << " -> " << mean1 << " %, p90 " << p90_0 << " -> " << p90_1 << " %");
  CHECK(mean1 < 0.1 * mean0);
  CHECK(p90_1 < 0.1 * p90_0);
  // As the transfer runs it (within a window around the start, the spatial term, both ways): as good.
  o = sdm::ZoomOutOptions();
  o.k_start = 10, o.k_end = 60, o.step = 5;
  const auto [mean2, p90_2] = euclidean_error(source, sdm::refine_correspondence(source, target, start, o), truth);
  INFO("windowed: mean " << mean2 << ", p90 " << p90_2 << " %");
  CHECK(mean2 < 0.3 * mean0);
  CHECK_THROWS_AS(sdm::refine_correspondence(source, target, std::vector<sdm::SourcePoint>(3), o), sdm::InputError);
}

TEST_CASE("zoomout with the discrete solver's energy: the bottle onto itself permuted and turned comes back", "[zoomout][discrete_map_energy]") {
  const sdm::Mesh source = sdm::make_primitive("bottle");
  // The target: the source's vertices in a shuffled order, turned; target vertex i truly is source
  // vertex perm[i].
  std::mt19937 rng(11);
  std::vector<int> perm = identity(source.n_vertices()), inverse(source.n_vertices());
  std::shuffle(perm.begin(), perm.end(), rng);
  for (size_t i = 0; i < perm.size(); ++i) inverse[size_t(perm[i])] = int(i);
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(1.0, Eigen::Vector3d(3, 1, 2).normalized()).toRotationMatrix();
  sdm::Mesh target;
  for (int s : perm) {
    const Eigen::Vector3d p = turn * sdm::point(source, source.vertex_handle(s));
    target.add_vertex(sdm::Mesh::Point(p.x(), p.y(), p.z()));
  }
  for (auto f : source.faces()) {
    std::vector<sdm::Mesh::VertexHandle> corners;
    for (auto v : source.fv_range(f)) corners.push_back(target.vertex_handle(inverse[size_t(v.idx())]));
    target.add_face(corners);
  }
  // The start: each true point moved by 3 % of the diagonal at random, back onto the surface.
  const sdm::TriangleBvh bvh(sdm::vertex_matrix(source), sdm::face_matrix(source));
  std::normal_distribution<double> noise(0, 0.03 * sdm::bounding_box_diagonal(source) / std::sqrt(3.0));
  std::vector<sdm::SourcePoint> truth, start;
  for (int s : perm) {
    const Eigen::Vector3d p = sdm::point(source, source.vertex_handle(s));
    truth.push_back(on_face(source, bvh.closest_point(p).face, p));
    const auto n = bvh.closest_point(p + Eigen::Vector3d(noise(rng), noise(rng), noise(rng)));
    start.push_back(on_face(source, n.face, n.point));
  }
  sdm::ZoomOutOptions o;
  o.k_start = 10, o.k_end = 60, o.step = 5;
  o.bijectivity_weight = 3, o.orthogonality_weight = 3, o.commutativity_weight = 1, o.orthogonal = false;
  const auto [mean0, p90_0] = euclidean_error(source, start, truth);
  const auto [mean1, p90_1] = euclidean_error(source, sdm::refine_correspondence(source, target, start, o), truth);
  INFO("mean " << mean0 << " -> " << mean1 << " %, p90 " << p90_0 << " -> " << p90_1 << " %");
  CHECK(mean1 < 0.1 * mean0);
  CHECK(p90_1 < 0.1 * p90_0);
}

TEST_CASE("sdm transfer between FAUST bodies, refined: the geodesic error per pair", "[zoomout][register_bodies]") {
  struct Pair {
    const char *source, *target;
    bool turned_scaled;  // the target turned 180 degrees about y and scaled 1.7 (faust::turned_scaled)
    double mean, p90;    // bounds (the literature's unit)
  };
  // Measured (refined; geodesics through 5 points per edge): 001 -> 007 (one person in two poses)
  // 1.03 / 2.38 (1.21 / 3.05 unrefined); 024 -> 007, the worst pair unrefined, 3.46 / 6.94 (4.24 /
  // 9.62), turned and scaled 3.51 / 7.09; the goal is p90 <= 8 per pair.
  const Pair pairs[] = {{"tr_reg_001.off", "tr_reg_007.off", false, 1.15, 2.6},
                        {"tr_reg_024.off", "tr_reg_007.off", false, 3.7, 7.5},
                        {"tr_reg_024.off", "tr_reg_007.off", true, 3.75, 7.6}};
  for (const Pair& p : pairs) {
    if (!faust::have(p.source) || !faust::have(p.target)) {
      WARN("no FAUST meshes at " << faust::humans_dir() << ": skipped");
      return;
    }
    test_util::TempDir dir;
    const sdm::Mesh a = faust::write_textured(p.source, dir / "a.obj", dir / "a.png");
    std::string target = faust::humans_dir() + "/" + p.target;
    if (p.turned_scaled) {
      sdm::write_mesh(faust::turned_scaled(sdm::load_mesh(target).mesh, 1.7), dir / "t.obj");
      target = dir / "t.obj";
    }
    const auto res = test_util::run_sdm("transfer --json --source " + (dir / "a.obj") + " --target " + target + " -o " + (dir / "b.obj") +
                                        " --size 256 --correspondence " + (dir / "c.txt"));
    INFO(res.output);
    REQUIRE(res.exit_code == 0);
    CHECK(test_util::last_json(res)["refined"] == true);
    const std::vector<sdm::SourcePoint> under = faust::read_correspondence(dir / "c.txt");
    REQUIRE(under.size() == a.n_vertices());
    const sdm::CorrespondenceError e = sdm::correspondence_error(a, under, identity(under.size()));
    std::fprintf(stderr, "%s -> %s%s refined: geodesic mean %.3f, p90 %.3f\n", p.source, p.target, p.turned_scaled ? " (turned, scaled)" : "",
                 e.geodesic_mean, e.geodesic_p90);
    CHECK(e.geodesic_mean < p.mean);
    CHECK(e.geodesic_p90 < p.p90);
  }
}

TEST_CASE("sdm transfer between FAUST_r bodies (own triangulations), refined: the geodesic error", "[zoomout][register_bodies]") {
  // humans_r 014 -> 026 (FAUST_r, Ren et al. 2018: each body remeshed on its own), measured at the
  // benchmark's 5000 ground-truth points (corres/NAME.vts: line k of both files the same point).
  // Measured through the command (the source as an OBJ with a planar uv): refined 3.28 / p90 6.77;
  // from the PLY-source start of "[refine_measure]" (3.25) 2.51 with orthogonal C, 2.77 without
  // (DECISIONS 5, "Spectral refinement"). The goal is 3.5 per pair.
  const std::string dir = faust::humans_dir() + "/../humans_r";
  if (!std::ifstream(dir + "/tr_reg_014.off").good() || !std::ifstream(dir + "/corres/tr_reg_026.vts").good()) {
    WARN("no FAUST_r meshes at " << dir << ": skipped");
    return;
  }
  test_util::TempDir tmp;
  const sdm::Mesh a = sdm::with_planar_uv(sdm::load_mesh(dir + "/tr_reg_014.off").mesh);
  sdm::write_png(sdm::Image(32, 32, 4, 255), tmp / "a.png");
  sdm::write_mesh(a, tmp / "a.obj", tmp / "a.png");
  const auto res = test_util::run_sdm("transfer --json --source " + (tmp / "a.obj") + " --target " + dir + "/tr_reg_026.off -o " + (tmp / "b.obj") +
                                      " --size 256 --correspondence " + (tmp / "c.txt"));
  INFO(res.output);
  REQUIRE(res.exit_code == 0);
  CHECK(test_util::last_json(res)["refined"] == true);
  const std::vector<sdm::SourcePoint> under = faust::read_correspondence(tmp / "c.txt");
  auto read_vts = [](const std::string& path) {
    std::ifstream in(path);
    std::vector<int> v;
    for (int i; in >> i;) v.push_back(i - 1);
    return v;
  };
  const std::vector<int> truth = read_vts(dir + "/corres/tr_reg_014.vts"), rows = read_vts(dir + "/corres/tr_reg_026.vts");
  REQUIRE(truth.size() == rows.size());
  std::vector<sdm::SourcePoint> at;
  for (int r : rows) {
    REQUIRE(r < int(under.size()));
    at.push_back(under[size_t(r)]);
  }
  const sdm::CorrespondenceError e = sdm::correspondence_error(a, at, truth);
  std::fprintf(stderr, "FAUST_r 014 -> 026 refined: geodesic mean %.3f, p90 %.3f\n", e.geodesic_mean, e.geodesic_p90);
  CHECK(e.geodesic_mean < 3.5);
  CHECK(e.geodesic_p90 < 7.2);
}

// ---- Measuring variants on the FAUST pairs (hidden) ----
//
// SDM_ZO_CACHE: a folder for the start correspondences (`sdm transfer --no-refine` of each ordered
// pair of 001, 007, 010, 024, written once); SDM_ZO_VARIANTS: variants separated by ';', each
// "k_start,k_end,step,spatial_weight,window[,bidirectional[,spatial_weight_end[,final_steps]]]"; SDM_ZO_PAIRS: how many of the 12 pairs (default all).
TEST_CASE("zoomout: variants on the FAUST pairs", "[.][zoomout_measure]") {
  const char* names[] = {"tr_reg_001.off", "tr_reg_007.off", "tr_reg_010.off", "tr_reg_024.off"};
  for (const char* n : names)
    if (!faust::have(n)) return;
  const std::string cache = std::getenv("SDM_ZO_CACHE") ? std::getenv("SDM_ZO_CACHE") : "/tmp/sdm-zoomout-cache";
  std::filesystem::create_directories(cache);
  const std::string variants = std::getenv("SDM_ZO_VARIANTS") ? std::getenv("SDM_ZO_VARIANTS") : "20,100,10,0,0";
  const int max_pairs = std::getenv("SDM_ZO_PAIRS") ? std::atoi(std::getenv("SDM_ZO_PAIRS")) : 12;
  std::vector<sdm::Mesh> meshes;
  std::vector<sdm::LaplaceBasis> bases;
  int k_max = 0;
  std::vector<sdm::ZoomOutOptions> opts;
  {
    std::stringstream all(variants);
    for (std::string v; std::getline(all, v, ';');) {
      sdm::ZoomOutOptions o;
      int bidirectional = 0;
      std::sscanf(v.c_str(), "%d,%d,%d,%lf,%lf,%d,%lf,%d", &o.k_start, &o.k_end, &o.step, &o.spatial_weight, &o.window, &bidirectional,
                  &o.spatial_weight_end, &o.final_steps);
      o.bidirectional = bidirectional != 0;
      opts.push_back(o), k_max = std::max(k_max, o.k_end);
    }
  }
  for (const char* n : names) {
    meshes.push_back(sdm::load_mesh(faust::humans_dir() + "/" + n).mesh);
    sdm::Stopwatch sw;
    bases.push_back(sdm::mesh_laplace_basis(meshes.back(), k_max));
    std::fprintf(stderr, "basis of %s: %d functions, %.2f s\n", n, k_max, sw.lap());
  }
  std::vector<std::vector<double>> sum(opts.size() + 1, std::vector<double>(2, 0));
  int pairs = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      if (i == j || pairs >= max_pairs) continue;
      ++pairs;
      const std::string file = cache + "/" + std::to_string(i) + "_" + std::to_string(j) + ".txt";
      if (!std::ifstream(file).good()) {
        test_util::TempDir dir;
        faust::write_textured(names[i], dir / "a.obj", dir / "a.png");
        const auto res = test_util::run_sdm("transfer --no-refine --source " + (dir / "a.obj") + " --target " + faust::humans_dir() + "/" +
                                            names[j] + " -o " + (dir / "b.obj") + " --size 256 --correspondence " + file);
        REQUIRE(res.exit_code == 0);
      }
      const std::vector<sdm::SourcePoint> start = faust::read_correspondence(file);
      const sdm::Mesh& a = meshes[size_t(i)];
      const sdm::CorrespondenceError e0 = sdm::correspondence_error(a, start, identity(start.size()));
      std::fprintf(stderr, "%s -> %s: start %.2f / %.2f", names[i], names[j], e0.geodesic_mean, e0.geodesic_p90);
      sum[0][0] += e0.geodesic_mean, sum[0][1] += e0.geodesic_p90;
      for (size_t v = 0; v < opts.size(); ++v) {
        sdm::Stopwatch sw;
        const auto map = sdm::zoomout(a, bases[size_t(i)], meshes[size_t(j)], bases[size_t(j)], start, opts[v]);
        const double s = sw.lap();
        const sdm::CorrespondenceError e = sdm::correspondence_error(a, map, identity(map.size()));
        std::fprintf(stderr, " | v%zu %.2f / %.2f (%.2f s)", v, e.geodesic_mean, e.geodesic_p90, s);
        sum[v + 1][0] += e.geodesic_mean, sum[v + 1][1] += e.geodesic_p90;
      }
      std::fprintf(stderr, "\n");
    }
  for (size_t v = 0; v <= opts.size(); ++v) std::fprintf(stderr, "%s: mean %.3f, mean p90 %.3f\n", v ? ("v" + std::to_string(v - 1)).c_str() : "start",
                                                       sum[v][0] / pairs, sum[v][1] / pairs);
}

// ---- Measuring variants on the remeshed benchmarks (hidden) ----
//
// As "[zoomout_measure]", over the pairs of SDM_ZO_SETS (',' separated; default all): "faust" (the
// 12 ordered pairs of 001, 007, 010, 024), "faust_r_tune" (humans_r 014 <-> 026), "faust_r_held"
// (humans_r 014, 026 <-> 038), "tosca_r" (centaur0 <-> centaur3, david6 <-> david12). FAUST_r and
// TOSCA_r are measured at their ground truth's points (corres/NAME.vts: line k of both files the
// same point). Variants: "[zoomout_measure]"'s fields, then orthogonal (0 or 1).
namespace {

struct MeasuredPair {
  std::string set, source, target;  // full paths
  std::string source_vts, target_vts;  // empty: vertex i corresponds
};

std::vector<MeasuredPair> measured_pairs(const std::string& sets) {
  const std::string humans = faust::humans_dir(), root = humans + "/..";
  std::vector<MeasuredPair> out;
  auto want = [&](const char* s) { return sets.empty() || ("," + sets + ",").find("," + std::string(s) + ",") != std::string::npos; };
  if (want("faust")) {
    const char* names[] = {"tr_reg_001", "tr_reg_007", "tr_reg_010", "tr_reg_024"};
    for (const char* a : names)
      for (const char* b : names)
        if (a != b) out.push_back({"faust", humans + "/" + a + ".off", humans + "/" + b + ".off", "", ""});
  }
  auto add = [&](const char* set, const std::string& dir, const std::string& a, const std::string& b) {
    for (int k = 0; k < 2; ++k) {
      const std::string& s = k ? b : a;
      const std::string& t = k ? a : b;
      out.push_back({set, dir + "/" + s + ".off", dir + "/" + t + ".off", dir + "/corres/" + s + ".vts", dir + "/corres/" + t + ".vts"});
    }
  };
  if (want("faust_r_tune")) add("faust_r_tune", root + "/humans_r", "tr_reg_014", "tr_reg_026");
  if (want("faust_r_held")) add("faust_r_held", root + "/humans_r", "tr_reg_014", "tr_reg_038"), add("faust_r_held", root + "/humans_r", "tr_reg_026", "tr_reg_038");
  if (want("tosca_r")) add("tosca_r", root + "/tosca_r", "centaur0", "centaur3"), add("tosca_r", root + "/tosca_r", "david6", "david12");
  return out;
}

std::vector<int> read_vts(const std::string& path) {
  std::ifstream in(path);
  std::vector<int> v;
  for (int i; in >> i;) v.push_back(i - 1);
  return v;
}

}  // namespace

TEST_CASE("zoomout: variants on the remeshed benchmarks", "[.][refine_measure]") {
  const std::string cache = std::getenv("SDM_ZO_CACHE") ? std::getenv("SDM_ZO_CACHE") : "/tmp/sdm-refine-cache";
  std::filesystem::create_directories(cache);
  const std::string variants = std::getenv("SDM_ZO_VARIANTS") ? std::getenv("SDM_ZO_VARIANTS") : "20,150,20,50,0.06,1,-1,4,0;20,150,20,50,0.06,1,-1,4,1";
  std::vector<sdm::ZoomOutOptions> opts;
  int k_max = 0;
  {
    std::stringstream all(variants);
    for (std::string v; std::getline(all, v, ';');) {
      sdm::ZoomOutOptions o;
      int bidirectional = 1, orthogonal = 1;
      std::sscanf(v.c_str(), "%d,%d,%d,%lf,%lf,%d,%lf,%d,%d", &o.k_start, &o.k_end, &o.step, &o.spatial_weight, &o.window, &bidirectional,
                  &o.spatial_weight_end, &o.final_steps, &orthogonal);
      o.bidirectional = bidirectional != 0, o.orthogonal = orthogonal != 0;
      opts.push_back(o), k_max = std::max(k_max, o.k_end);
    }
  }
  std::map<std::string, std::pair<sdm::Mesh, sdm::LaplaceBasis>> meshes;
  auto mesh = [&](const std::string& path) -> const std::pair<sdm::Mesh, sdm::LaplaceBasis>& {
    auto it = meshes.find(path);
    if (it != meshes.end()) return it->second;
    sdm::Mesh m = sdm::load_mesh(path).mesh;
    sdm::LaplaceBasis b = sdm::mesh_laplace_basis(m, k_max);
    return meshes.emplace(path, std::make_pair(std::move(m), std::move(b))).first->second;
  };
  std::map<std::string, std::vector<std::vector<double>>> sums;
  std::map<std::string, int> counts;
  for (const MeasuredPair& p : measured_pairs(std::getenv("SDM_ZO_SETS") ? std::getenv("SDM_ZO_SETS") : "")) {
    if (!std::ifstream(p.source).good() || !std::ifstream(p.target).good()) continue;
    const std::string stem_s = std::filesystem::path(p.source).stem(), stem_t = std::filesystem::path(p.target).stem();
    const std::string file = cache + "/" + stem_s + "__" + stem_t + ".txt";
    if (!std::ifstream(file).good()) {
      test_util::TempDir dir;
      sdm::Image tex(32, 32, 4, 255);
      sdm::write_png(tex, dir / "a.png");
      sdm::write_mesh(sdm::with_planar_uv(sdm::load_mesh(p.source).mesh), dir / "a.obj", dir / "a.png");
      const auto res = test_util::run_sdm("transfer --no-refine --force --source " + (dir / "a.obj") + " --target " + p.target + " -o " + (dir / "b.obj") +
                                          " --size 256 --correspondence " + file);
      INFO(res.output);
      REQUIRE(res.exit_code == 0);
    }
    const std::vector<sdm::SourcePoint> start = faust::read_correspondence(file);
    const auto& [a, ba] = mesh(p.source);
    const auto& [b, bb] = mesh(p.target);
    std::vector<int> rows, truth;  // the target vertices measured and their true source vertices
    if (p.source_vts.empty()) rows = identity(start.size()), truth = rows;
    else truth = read_vts(p.source_vts), rows = read_vts(p.target_vts);
    auto error = [&](const std::vector<sdm::SourcePoint>& map) {
      std::vector<sdm::SourcePoint> at;
      for (int r : rows) at.push_back(map[size_t(r)]);
      return sdm::correspondence_error(a, at, truth);
    };
    auto& sum = sums[p.set];
    sum.resize(opts.size() + 1, std::vector<double>(2, 0));
    ++counts[p.set];
    const sdm::CorrespondenceError e0 = error(start);
    std::fprintf(stderr, "%s -> %s: start %.2f / %.2f", stem_s.c_str(), stem_t.c_str(), e0.geodesic_mean, e0.geodesic_p90);
    sum[0][0] += e0.geodesic_mean, sum[0][1] += e0.geodesic_p90;
    for (size_t v = 0; v < opts.size(); ++v) {
      sdm::Stopwatch sw;
      const auto map = sdm::zoomout(a, ba, b, bb, start, opts[v]);
      const double s = sw.lap();
      const sdm::CorrespondenceError e = error(map);
      std::fprintf(stderr, " | v%zu %.2f / %.2f (%.2f s)", v, e.geodesic_mean, e.geodesic_p90, s);
      sum[v + 1][0] += e.geodesic_mean, sum[v + 1][1] += e.geodesic_p90;
    }
    std::fprintf(stderr, "\n");
  }
  for (const auto& [set, sum] : sums)
    for (size_t v = 0; v < sum.size(); ++v)
      std::fprintf(stderr, "%s %s: mean %.3f, mean p90 %.3f\n", set.c_str(), v ? ("v" + std::to_string(v - 1)).c_str() : "start",
                   sum[v][0] / counts[set], sum[v][1] / counts[set]);
}
