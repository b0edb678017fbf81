// Each stage of the skeleton extraction called alone (contract_mesh.h, surgery.h,
// refine_skeleton.h, choose_candidate.h) and the helpers they run on (four_ary_heap.h,
// core/parallel.h), checked with numbers from geometry.
#include "libstm/core/parallel.h"
#include "libstm/mesh/inside_mesh.h"
#include "libstm/geometry/triangle_bvh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/primitives.h"
#include "libstm/skeleton/choose_candidate.h"
#include "libstm/skeleton/contract_mesh.h"
#include "libstm/skeleton/four_ary_heap.h"
#include "libstm/skeleton/medial_poles.h"
#include "libstm/skeleton/refine_skeleton.h"
#include "libstm/skeleton/surgery.h"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace {

struct Contracted {
  Eigen::MatrixX3d V, P;  // original and contracted positions
  Eigen::MatrixX3i F;
  sdm::ContractResult result;
};

Contracted contract(const std::string& name) {
  Contracted c;
  const sdm::Mesh m = sdm::make_primitive(name);
  c.V = sdm::vertex_matrix(m);
  c.F = sdm::face_matrix(m);
  c.result = sdm::contract_mesh(c.V, c.F, sdm::SkeletonOptions().raw_contraction);
  c.P = c.result.positions;
  return c;
}

int junctions(const sdm::SkeletonGraph& g) {
  const std::vector<int> deg = g.degrees();
  return int(std::count_if(deg.begin(), deg.end(), [](int d) { return d >= 3; }));
}

int cycles(const sdm::SkeletonGraph& g) { return int(g.edges.size()) - int(g.pos.size()) + 1; }

// Every vertex in exactly one node's cluster.
bool partitions(const sdm::SkeletonGraph& g, int vertices) {
  std::vector<int> owners(vertices, 0);
  for (const auto& vs : g.verts)
    for (int v : vs) ++owners[v];
  return std::all_of(owners.begin(), owners.end(), [](int k) { return k == 1; });
}

Eigen::Vector3d centroid(const Eigen::MatrixX3d& V, const std::vector<int>& vs) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int v : vs) c += V.row(v).transpose();
  return c / double(vs.size());
}

// A graph of `n` nodes on the circle of radius 1 around z, in a ring (closed) or a chain (open).
sdm::SkeletonGraph circle_graph(int n, bool closed) {
  sdm::SkeletonGraph g;
  for (int k = 0; k < n; ++k) {
    const double a = 2 * M_PI * k / n;
    g.pos.emplace_back(std::cos(a), std::sin(a), 0.0);
    g.fallback.push_back(g.pos.back());
    g.verts.push_back({k});
    if (k + 1 < n) g.edges.insert({k, k + 1});
  }
  if (closed) g.edges.insert({0, n - 1});
  return g;
}

}  // namespace

TEST_CASE("contraction alone shrinks the ypsilon to a thin shape", "[skeleton][steps]") {
  const Contracted c = contract("ypsilon");
  // Measured: area ratio 1.3e-6 after 14 iterations.
  REQUIRE(c.result.iterations > 0);
  CHECK(c.result.area_ratio.back() < 1e-5);
  for (size_t k = 1; k < c.result.area_ratio.size(); ++k) CHECK(c.result.area_ratio[k] < c.result.area_ratio[k - 1]);
  CHECK(c.P.allFinite());
}

TEST_CASE("surgery alone turns the contracted ypsilon into a Y and the donut into a ring", "[skeleton][steps]") {
  SECTION("ypsilon: 3 ends, 1 junction, no cycle, every vertex mapped") {
    const Contracted c = contract("ypsilon");
    const sdm::InsideMesh in(c.V, c.F);
    sdm::SkeletonStats st;
    const sdm::SkeletonGraph g = sdm::connectivity_surgery(c.V, c.P, c.F, in, 0, {}, &st);
    CHECK(g.ends() == 3);
    CHECK(junctions(g) == 1);
    CHECK(cycles(g) == 0);
    CHECK(partitions(g, int(c.V.rows())));
    CHECK(st.refused_collapses == 0);  // genus 0: no collapse is tested against the volume
    // Nodes sit at the centroids of the original positions of their clusters.
    for (size_t a = 0; a < g.pos.size(); ++a) CHECK((g.pos[a] - centroid(c.V, g.verts[a])).norm() < 1e-12);
  }
  SECTION("donut (genus 1): exactly one cycle") {
    const Contracted c = contract("donut");
    const sdm::InsideMesh in(c.V, c.F);
    const sdm::SkeletonGraph g = sdm::connectivity_surgery(c.V, c.P, c.F, in, 1, {});
    CHECK(cycles(g) == 1);
    CHECK(g.ends() == 0);
    CHECK(partitions(g, int(c.V.rows())));
  }
}

TEST_CASE("refinement alone keeps the ypsilon's nodes inside and at their centroids", "[skeleton][steps]") {
  const Contracted c = contract("ypsilon");
  const sdm::InsideMesh in(c.V, c.F);
  const sdm::SkeletonGraph cut = sdm::connectivity_surgery(c.V, c.P, c.F, in, 0, {});
  sdm::SkeletonGraph g = cut;
  const sdm::TriangleBvh surface(c.V, c.F);
  const double diag = (c.V.colwise().maxCoeff() - c.V.colwise().minCoeff()).norm();
  sdm::refine_skeleton(g, c.V, in, surface, diag, {});
  REQUIRE(g.pos.size() < cut.pos.size());  // short edges were merged (measured: 16 -> 12 nodes)
  CHECK(g.ends() == 3);
  CHECK(junctions(g) == 1);
  CHECK(cycles(g) == 0);
  CHECK(partitions(g, int(c.V.rows())));
  for (const auto& p : g.pos) CHECK(in.inside(p));
  for (const auto& [a, b] : g.edges) CHECK(in.segment_inside(g.pos[a], g.pos[b]));
  // A node the refinement did not merge stays at the centroid of its vertices whenever that point
  // and its edges lie inside (the code moves a node only when they do not).
  const auto adj = g.adjacency();
  int unmerged_checked = 0;
  for (size_t a = 0; a < g.pos.size(); ++a) {
    const bool unmerged =
        std::any_of(cut.verts.begin(), cut.verts.end(), [&](const std::vector<int>& vs) { return vs == g.verts[a]; });
    const Eigen::Vector3d c0 = centroid(c.V, g.verts[a]);
    bool ok = in.inside(c0);
    for (int b : adj[a]) ok = ok && !in.segment_crosses(c0, g.pos[b]);
    if (!unmerged || !ok) continue;
    ++unmerged_checked;
    CHECK((g.pos[a] - c0).norm() < 1e-12);
  }
  CHECK(unmerged_checked >= 3);
}

TEST_CASE("candidate choice: cycles equal to the genus first, then the handicapped tube error", "[skeleton][steps]") {
  const sdm::Mesh donut = sdm::make_primitive("donut");
  const Eigen::MatrixX3d V = sdm::vertex_matrix(donut);
  const Eigen::MatrixX3i F = sdm::face_matrix(donut);
  const sdm::InsideMesh in(V, F);
  const Eigen::MatrixX3d poles = sdm::medial_poles(V, F);
  const double diag = (V.colwise().maxCoeff() - V.colwise().minCoeff()).norm();
  // The donut's core circle (major radius 1) as a ring, and the same circle cut open.
  const sdm::SkeletonCandidate ring = sdm::measure_candidate(circle_graph(24, true), in, V, F, &poles, diag);
  sdm::SkeletonCandidate chain = sdm::measure_candidate(circle_graph(24, false), in, V, F, &poles, diag);
  REQUIRE(ring.cycles == 1);
  REQUIRE(chain.cycles == 0);
  CHECK(ring.outside == 0);
  CHECK(ring.error < 0.01);  // the surface is a tube of the medial radius around the circle
  chain.error = ring.error / 10;  // even a much smaller error does not make up for a lost cycle
  const sdm::SkeletonOptions opt;
  CHECK(sdm::choose_candidate(ring, chain, 1, opt) == sdm::SkeletonMethod::contraction);
  CHECK(sdm::choose_candidate(chain, ring, 1, opt) == sdm::SkeletonMethod::medial);
  // Same cycles: the medial candidate must beat the contraction's error by the handicap (2).
  sdm::SkeletonCandidate a = ring, b = ring;
  a.error = 0.1, b.error = 0.06;
  CHECK(sdm::choose_candidate(a, b, 1, opt) == sdm::SkeletonMethod::contraction);
  b.error = 0.04;
  CHECK(sdm::choose_candidate(a, b, 1, opt) == sdm::SkeletonMethod::medial);
  // An explicit method is obeyed.
  sdm::SkeletonOptions contraction_only;
  contraction_only.method = sdm::SkeletonMethod::contraction;
  CHECK(sdm::choose_candidate(a, b, 1, contraction_only) == sdm::SkeletonMethod::contraction);
}

TEST_CASE("a circle through the donut explains its surface, its centre alone does not", "[skeleton][steps]") {
  const sdm::Mesh donut = sdm::make_primitive("donut");
  const Eigen::MatrixX3d V = sdm::vertex_matrix(donut);
  const Eigen::MatrixX3i F = sdm::face_matrix(donut);
  const Eigen::MatrixX3d poles = sdm::medial_poles(V, F);
  sdm::SkeletonGraph centre;
  centre.pos = {Eigen::Vector3d::Zero()};
  // Distance to the skeleton 1 +- 0.4 against a medial radius of 0.4: an error of about 0.6.
  CHECK(sdm::tube_error(centre, V, F, poles) > 0.5);
  CHECK(sdm::tube_error(circle_graph(48, true), V, F, poles) < 0.02);
}

TEST_CASE("four-ary heap pops in order and sweeps stale entries", "[skeleton][steps]") {
  sdm::FourAryHeap<int> heap;
  std::vector<int> values;
  for (int k = 0; k < 200; ++k) values.push_back((k * 7919) % 211);
  for (int v : values) heap.push(v);
  heap.sweep([](int v) { return v % 3 == 0; });
  std::vector<int> expected;
  for (int v : values)
    if (v % 3 != 0) expected.push_back(v);
  std::sort(expected.begin(), expected.end());
  std::vector<int> popped;
  while (!heap.empty()) popped.push_back(heap.pop());
  CHECK(popped == expected);
}

TEST_CASE("parallel helpers: both callables run, failures come back, a shared loop covers every index once", "[core]") {
  int a = 0, b = 0;
  sdm::run_concurrently([&] { a = 1; }, [&] { b = 2; });
  CHECK(a + b == 3);
  CHECK_THROWS_WITH(sdm::run_concurrently([] { throw std::runtime_error("background"); }, [] {}), "background");
  // The calling thread's failure comes first.
  CHECK_THROWS_WITH(sdm::run_concurrently([] { throw std::runtime_error("background"); },
                                          [] { throw std::runtime_error("here"); }),
                    "here");
  sdm::BackgroundTask task([] { throw std::logic_error("task"); });
  CHECK_THROWS_AS(task.wait(), std::logic_error);
  CHECK_NOTHROW(task.wait());  // rethrown once

  std::vector<int> hits(1000, 0);
  sdm::SharedLoop loop(int(hits.size()), 32, [&](int i) { ++hits[i]; });
  sdm::run_concurrently([&] { loop.work(); }, [&] { loop.work(); });
  loop.wait();
  CHECK(std::all_of(hits.begin(), hits.end(), [](int h) { return h == 1; }));
  sdm::SharedLoop failing(100, 8, [](int i) {
    if (i == 50) throw std::runtime_error("index 50");
  });
  failing.work();
  CHECK_THROWS_WITH(failing.wait(), "index 50");
}

