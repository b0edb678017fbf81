// Texture transfer between different bodies as a user runs it (the band test): the source
// is written as a PLY whose vertex colours paint five bands (head, left hand, right hand, left
// foot, right foot: geodesic balls around annotated landmark vertices), `sdm transfer` carries
// them onto another body (--vertex-colors), and on the target each band must lie on the same part
// (a geodesic ball 1.6 times as large around the target's landmark) and cover its core. Measured
// per target vertex, area-weighted (what the target's renders show, without the views' occlusion).
//
// Landmarks (vertex indices into the files of ../shared/models/humans). FAUST registrations have
// SMPL's topology, so SMPL's vertex ids hold for tr_reg_007 and tr_reg_024: 411 the top of the
// head, 2445 / 5905 the left / right middle fingertip, 3216 / 6617 the left / right big toe.
// tr_reg_085 (remeshed) and the TOSCA models: the geodesic extremities (farthest-point sampling
// from the vertex nearest the centroid) for hands and feet, left and right told from the side of
// the body their upper arm or thigh lies on, the facing direction read from renders; the TOSCA
// heads at the top of the head on the symmetry plane (the crown: both lie along z, head up).
// A part is the surface within 1.6 band radii of its landmark (along edges), except the gorilla's
// head: its muzzle juts forward and down from the crown, its front 0.16-0.19 of the diagonal away
// along the surface though 0.09-0.13 in space (the 62 vertices of the man's head band
// that fell outside 0.16 lay there, on the face's symmetry plane), so its head part reaches 0.19.
#include "test_util.h"
#include "faust_pairs.h"

#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/mesh_geometry.h"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace {

struct Body {
  const char* file;
  std::array<int, 5> landmark;  // head, left hand, right hand, left foot, right foot
  double head_part = 0.16;      // the head part's reach from the crown along the surface (fraction of the diagonal)
};

const Body kBodies[] = {{"tr_reg_007.off", {411, 2445, 5905, 3216, 6617}},
                        {"tr_reg_024.off", {411, 2445, 5905, 3216, 6617}},
                        {"tr_reg_085.off", {138, 1840, 4345, 2350, 4826}},
                        {"8_gorilla_01.off", {889, 3401, 2374, 4976, 4179}, 0.19},
                        {"8_man_02.off", {2982, 962, 228, 4617, 513}}};
const char* kPart[5] = {"head", "left hand", "right hand", "left foot", "right foot"};
const double kRadius[5] = {0.10, 0.07, 0.07, 0.07, 0.07};  // band radii, fractions of the diagonal
const Eigen::Vector3f kColor[5] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, 0, 1}};

// Distance along edges from vertex `from`, as a fraction of the diagonal.
std::vector<double> geodesic(const sdm::Mesh& m, int from) {
  std::vector<double> d = sdm::edge_path_distances(m, from);
  const double diag = sdm::bounding_box_diagonal(m);
  for (double& x : d) x /= diag;
  return d;
}

struct Bands {
  int exit_code = -1;
  std::string output;
  double on_part[5] = {0, 0, 0, 0, 0};  // share of each band's area on the target's part
  double core[5] = {0, 0, 0, 0, 0};     // share of the part's core showing the band
};

// The bands of src carried onto tgt (target_file: tgt written otherwise, the same vertices), the
// source first moved by up to 1e-7 of its diagonal when source_seed is not 0.
Bands transfer_bands(const Body& src, const Body& tgt, const std::string& target_file = "", uint32_t source_seed = 0) {
  Bands r;
  test_util::TempDir dir;
  sdm::Mesh a = sdm::load_mesh(faust::humans_dir() + "/" + src.file).mesh;
  if (source_seed) {
    const double diag = sdm::bounding_box_diagonal(a);
    uint32_t x = source_seed;
    for (auto v : a.vertices()) {
      auto p = a.point(v);
      for (int c = 0; c < 3; ++c) {
        x = x * 1664525u + 1013904223u;
        p[c] += 1e-7 * diag * (double(x >> 8) / double(1u << 24) - 0.5);
      }
      a.set_point(v, p);
    }
  }
  std::vector<Eigen::Vector3f> color(a.n_vertices(), Eigen::Vector3f(0.5f, 0.5f, 0.5f));
  for (int k = 0; k < 5; ++k) {
    const std::vector<double> g = geodesic(a, src.landmark[k]);
    for (size_t v = 0; v < g.size(); ++v)
      if (g[v] < kRadius[k]) color[v] = kColor[k];
  }
  sdm::write_colored_ply(a, color, dir / "source.ply");
  if (const char* dump = std::getenv("SDM_TEST_DUMP"))  // the painted source, to run sdm transfer on by hand
    std::filesystem::copy_file(dir / "source.ply", std::string(dump) + "/bands_" + src.file + ".ply",
                               std::filesystem::copy_options::overwrite_existing);
  const std::string target = target_file.empty() ? faust::humans_dir() + "/" + tgt.file : target_file;
  const auto res = test_util::run_sdm("transfer --source " + (dir / "source.ply") + " --target " + target + " -o " + (dir / "t.obj") +
                                      " --size 512 --vertex-colors " + (dir / "t.ply"));
  r.exit_code = res.exit_code, r.output = res.output;
  if (res.exit_code != 0) return r;
  std::vector<Eigen::Vector3f> got;
  sdm::LoadedMesh b_read = sdm::load_mesh(dir / "t.ply");
  got = std::move(b_read.colors);
  const sdm::Mesh b = std::move(b_read.mesh);
  const sdm::Mesh b0 = sdm::load_mesh(faust::humans_dir() + "/" + tgt.file).mesh;
  REQUIRE(got.size() == b0.n_vertices());
  const std::vector<double> area = sdm::vertex_areas(b0);
  for (int k = 0; k < 5; ++k) {
    const std::vector<double> g = geodesic(b0, tgt.landmark[k]);
    double band = 0, on = 0, core = 0, core_band = 0;
    const double reach = k == 0 ? tgt.head_part : 1.6 * kRadius[k];
    for (size_t v = 0; v < got.size(); ++v) {
      const bool in_band = (got[v] - kColor[k]).cwiseAbs().maxCoeff() < 0.25f;
      band += in_band * area[v], on += (in_band && g[v] < reach) * area[v];
      if (g[v] < 0.5 * kRadius[k]) core += area[v], core_band += in_band * area[v];
    }
    r.on_part[k] = band > 0 ? on / band : 0, r.core[k] = core > 0 ? core_band / core : 0;
  }
  return r;
}

std::string describe(const Bands& r) {
  std::string s;
  char line[160];
  for (int k = 0; k < 5; ++k) {
    std::snprintf(line, sizeof line, "  %-10s %5.1f %% of the band on it, %5.1f %% of its core covered\n", kPart[k], 100 * r.on_part[k],
                  100 * r.core[k]);
    s += line;
  }
  return s;
}

void check_bands(const Body& src, const Body& tgt) {
  if (!faust::have(src.file) || !faust::have(tgt.file)) {
    WARN("no " << src.file << " or " << tgt.file << " at " << faust::humans_dir() << ": skipped");
    return;
  }
  const Bands r = transfer_bands(src, tgt);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  std::fprintf(stderr, "%s -> %s:\n%s", src.file, tgt.file, describe(r).c_str());
  for (int k = 0; k < 5; ++k) {
    INFO(kPart[k]);
    CHECK(r.on_part[k] >= 0.9);
    CHECK(r.core[k] >= 0.3);
  }
}

// A transfer that must either land every band on its part (>= 90 %) or refuse with exit 2, its
// message naming the refusal and the way out.
void check_right_or_refused(const Bands& r, const std::string& refusal, const std::string& way_out) {
  INFO(r.output);
  if (r.exit_code == 2) {
    CHECK(r.output.find(refusal) != std::string::npos);
    CHECK(r.output.find(way_out) != std::string::npos);
    return;
  }
  REQUIRE(r.exit_code == 0);
  for (int k = 0; k < 5; ++k) {
    INFO(kPart[k]);
    CHECK(r.on_part[k] >= 0.9);
  }
}

// The parts of src carried onto tgt as a user with a textured model runs it: src written as an OBJ
// with a planar uv and a texture (its coordinates to 17 digits, exactly those of the OFF file: the
// band test's PLY holds floats, and the extraction changes with the last bits), `sdm transfer
// --correspondence` onto the OFF file of tgt. Per part of the target (head, hands, feet: the
// vertices within the band radius of its landmark), the share of its vertices whose source point
// lies nearest the same part's landmark of the source among the five (exit code and output kept).
struct Parts {
  int exit_code = -1;
  std::string output;
  double right[5] = {0, 0, 0, 0, 0};
};

Parts transfer_parts(const Body& src, const Body& tgt) {
  Parts r;
  test_util::TempDir dir;
  const sdm::Mesh a = faust::write_textured(src.file, dir / "a.obj", dir / "a.png");
  const auto res = test_util::run_sdm("transfer --source " + (dir / "a.obj") + " --target " + faust::humans_dir() + "/" + tgt.file + " -o " +
                                      (dir / "b.obj") + " --size 256 --correspondence " + (dir / "c.txt"));
  r.exit_code = res.exit_code, r.output = res.output;
  if (res.exit_code != 0) return r;
  const sdm::Mesh b = sdm::load_mesh(faust::humans_dir() + "/" + tgt.file).mesh;
  std::vector<Eigen::Vector3d> under;  // per target vertex, its source point
  for (const sdm::SourcePoint& q : faust::read_correspondence(dir / "c.txt")) {
    REQUIRE((q.face >= 0 && q.face < int(a.n_faces())));
    under.push_back(faust::point_under(a, q));
  }
  REQUIRE(under.size() == b.n_vertices());
  for (int k = 0; k < 5; ++k) {
    const std::vector<double> g = geodesic(b, tgt.landmark[k]);
    double part = 0, right = 0;
    for (size_t v = 0; v < g.size(); ++v) {
      if (g[v] >= kRadius[k]) continue;
      int nearest = 0;
      for (int q = 1; q < 5; ++q)
        if ((under[v] - sdm::point(a, a.vertex_handle(src.landmark[q]))).norm() <
            (under[v] - sdm::point(a, a.vertex_handle(src.landmark[nearest]))).norm())
          nearest = q;
      part += 1, right += nearest == k;
    }
    r.right[k] = part > 0 ? right / part : 0;
  }
  return r;
}

// Each part of tgt shows src's same part (>= 90 % of its vertices).
void check_parts(const Body& src, const Body& tgt) {
  if (!faust::have(src.file) || !faust::have(tgt.file)) return;
  const Parts r = transfer_parts(src, tgt);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  for (int k = 0; k < 5; ++k) {
    std::fprintf(stderr, "%s -> %s: %-10s %5.1f %% of its vertices on the source's %s\n", src.file, tgt.file, kPart[k], 100 * r.right[k], kPart[k]);
    INFO(kPart[k]);
    CHECK(r.right[k] >= 0.9);
  }
}

}  // namespace

// From the files' own coordinates (an OBJ as written by a user's tool), FAUST 024 and the TOSCA man
// crossed their hands either way under the rule before the candidate score: the candidate that turned parts least crossed the
// hands, its limbs meeting the torso 1.9 times as far apart as the right match's, which turned
// parts 10 % more. The score weighs the three measures together now (choose_candidate).
TEST_CASE("sdm transfer: FAUST 024 and the TOSCA man keep left and right from the files' own coordinates", "[transfer_bands]") {
  check_parts(kBodies[1], kBodies[4]);
  check_parts(kBodies[4], kBodies[1]);
}

// Some extractions of tr_reg_007 (its torso is nearly a sheet) hang an arm from the pelvis; before
// common_branching slid it to the chest, a source written like this one had its head's band
// land on a foot of 024.
TEST_CASE("sdm transfer: head, hands and feet land on head, hands and feet, FAUST 007 onto 024", "[transfer_bands]") {
  check_bands(kBodies[0], kBodies[1]);
}

TEST_CASE("sdm transfer: head, hands and feet land on head, hands and feet, FAUST 024 onto 007", "[transfer_bands]") {
  check_bands(kBodies[1], kBodies[0]);
}

// Another body remeshed (other triangles, no vertex correspondence): before the transfer took the
// medial skeleton, tr_reg_085's had no head and the bands landed on other parts.
TEST_CASE("sdm transfer: head, hands and feet land on head, hands and feet, FAUST 007 onto 085", "[transfer_bands]") {
  check_bands(kBodies[0], kBodies[2]);
}

// Two people whose shapes are close enough for the source to be bent along its own skeleton within
// the bent path's bounds (0.36-0.38 % RMS): 024 raises its right leg, 085 stands, and bent that way
// the raised leg crumpled at the knee and the right foot's band covered 085's foot and shin (39.7 %
// of it on the foot). Registered as another body the source fits closer (0.29-0.30 %) and that fit
// is taken (transfer_texture's recognise_or_register).
TEST_CASE("sdm transfer: FAUST 024 and 085 take the closer registration as another body over the bent source", "[transfer_bands]") {
  for (const auto& [src, tgt] : {std::pair{kBodies[1], kBodies[2]}, std::pair{kBodies[2], kBodies[1]}}) {
    if (!faust::have(src.file) || !faust::have(tgt.file)) return;
    const Bands r = transfer_bands(src, tgt);
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    std::fprintf(stderr, "%s -> %s:\n%s", src.file, tgt.file, describe(r).c_str());
    CHECK(r.output.find("the target is another body") != std::string::npos);
    for (int k = 0; k < 5; ++k) {
      INFO(kPart[k]);
      CHECK(r.on_part[k] >= 0.9);
      CHECK(r.core[k] >= 0.3);
    }
  }
}

// Another animal of the same kind: the gorilla's arms are longer than its legs and a man's shorter.
TEST_CASE("sdm transfer: head, hands and feet land on head, hands and feet, TOSCA gorilla onto man", "[transfer_bands]") {
  check_bands(kBodies[3], kBodies[4]);
}

TEST_CASE("sdm transfer: head, hands and feet land on head, hands and feet, TOSCA man onto gorilla", "[transfer_bands]") {
  check_bands(kBodies[4], kBodies[3]);
}

// Across the data sets. FAUST 024 onto the TOSCA man: a candidate with the hands crossed fit 5.6 %
// closer than the right one at 2 % more twist and was taken (hand bands on the other hand); the
// places where its limbs meet the torso lie 1.63 times as far apart (attachment 5.7 % against 3.5 %),
// which now keeps it from taking over on fit.
TEST_CASE("sdm transfer: head, hands and feet land on head, hands and feet, FAUST 024 onto TOSCA man", "[transfer_bands]") {
  check_bands(kBodies[1], kBodies[4]);
}

// The TOSCA man onto FAUST 007 crossed the hands silently under an older rule: its right match changed the
// distances between the extremities most, as 007's raised foot touches its other knee and the foot's
// tip landed there, and was left out before twist and fit were compared. The raised foot's band
// spilled onto the knee it touches (79.5 % on the foot at first, 89.1 % once the target's points
// took faces facing their way); since the correspondence's islands are mended (mend_islands) every band lands on its part, as from the gorilla and FAUST 085 (82.9 and 85.0 %
// before).
TEST_CASE("sdm transfer: the TOSCA man, the gorilla and FAUST 085 onto FAUST 007 keep the raised foot", "[transfer_bands]") {
  for (const Body* src : {&kBodies[4], &kBodies[3], &kBodies[2]}) {
    if (!faust::have(src->file) || !faust::have(kBodies[0].file)) return;
    const Bands r = transfer_bands(*src, kBodies[0]);
    INFO(r.output);
    REQUIRE(r.exit_code == 0);
    std::fprintf(stderr, "%s -> tr_reg_007.off:\n%s", src->file, describe(r).c_str());
    for (int k = 0; k < 5; ++k) {
      INFO(src->file << ": " << kPart[k]);
      CHECK(r.on_part[k] >= 0.9);
    }
  }
}

// The TOSCA man onto FAUST 024: both skeletons fork a foot and the man's head slides to another
// junction, so every candidate pairs limbs with other limbs (the attachments 9.1 % apart) while
// the non-rigid fit still lays the surfaces 0.5 % apart. Right or refused, never the scramble it wrote.
// The refusal now first tries the models' other extraction candidates: with 024's
// contraction skeleton every band lands on its part (100 %).
TEST_CASE("sdm transfer: limbs matched to other limbs are refused, not written", "[transfer_bands]") {
  if (!faust::have(kBodies[4].file) || !faust::have(kBodies[1].file)) return;
  check_right_or_refused(transfer_bands(kBodies[4], kBodies[1]), "matched to other branches", "--force");
}

// FAUST 085 onto the TOSCA gorilla landed hands on feet and feet on hands, silently: the gorilla's
// medial skeleton joins head, arms and legs within 0.5 % of its length, and the reduction slid 085's
// head to its hips to agree with it, pairing legs with arms. No skeleton is slid to agree with one
// whose junctions nearly coincide (common_branching), and the gorilla's other candidate was then
// refused (limbs meeting the torso 5.7 % apart). Now every pair of the two
// models' candidates is registered and the closest fit kept: both other candidates (0.292 % RMS,
// attachments 3.0 % apart) lay every band on its part (95.1 % for the worst, measured).
TEST_CASE("sdm transfer: FAUST 085 onto the TOSCA gorilla takes the pair of candidates that fits", "[transfer_bands]") {
  if (!faust::have(kBodies[2].file) || !faust::have(kBodies[3].file)) return;
  const Bands r = transfer_bands(kBodies[2], kBodies[3]);
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  std::fprintf(stderr, "tr_reg_085.off -> 8_gorilla_01.off:\n%s", describe(r).c_str());
  for (int k = 0; k < 5; ++k) {
    INFO(kPart[k]);
    CHECK(r.on_part[k] >= 0.9);
  }
}

// `sdm bench --transfer` reads the gorilla from its OFF file, whose extraction puts the legs at one
// junction and the head and arms at another 0.5 % of the length away: every place where a limb meets
// that core surrounds one point, the attachments of every candidate measured 9-10 % apart from the
// man's, and the first cut of the 5 % refusal refused the benchmark. The attachments are now
// compared only where both cores span 3 % of their skeletons. All three pairs register and fit.
TEST_CASE("sdm bench --transfer registers all three pairs", "[transfer_bands]") {
  if (!faust::have(kBodies[3].file) || !faust::have(kBodies[4].file) || !faust::have(kBodies[0].file)) return;
  const auto res = test_util::run_sdm("bench --transfer --repeat 1 --json --humans " + faust::humans_dir());
  INFO(res.output);
  REQUIRE(res.exit_code == 0);
  const nlohmann::json j = test_util::last_json(res);
  REQUIRE(j.at("transfers").size() == 3);
  for (const auto& t : j.at("transfers")) {
    INFO(t.dump());
    CHECK(t.at("target_skeleton") == "registered");
    CHECK(t.at("fit_rms").get<double>() < 0.01);
  }
}

// The other directions, measured (hidden: run with [bands_measure]); see docs/BENCHMARKS.md.
TEST_CASE("band transfer on the other pairs, measured", "[.][bands_measure]") {
  // ... and across the data sets: the TOSCA man and FAUST 007.
  for (auto [s, t] : {std::pair<int, int>{2, 0}, {1, 2}, {2, 1}, {4, 0}, {0, 4}}) {
    if (!faust::have(kBodies[s].file) || !faust::have(kBodies[t].file)) continue;
    const Bands r = transfer_bands(kBodies[s], kBodies[t]);
    std::fprintf(stderr, "%s -> %s: exit %d\n%s", kBodies[s].file, kBodies[t].file, r.exit_code,
                 r.exit_code == 0 ? describe(r).c_str() : (r.output.substr(r.output.rfind("error")) + "\n").c_str());
  }
}

namespace {

// Variant k of target b, written into dir: 0 as a float PLY, 1 as an OBJ, 2 turned 90 degrees about
// x (lying down), 3 scaled by 1.7, 4 every coordinate moved by up to 1e-6 of the diagonal, 5 and on
// by up to 1e-7 (a seed each). The vertices keep their order, so the landmarks hold.
std::string write_variant(const sdm::Mesh& b, int k, const test_util::TempDir& dir) {
  const double diag = sdm::bounding_box_diagonal(b);
  sdm::Mesh m = b;
  uint32_t seed = 12345 + 7919 * uint32_t(k);
  for (auto v : m.vertices()) {
    auto p = m.point(v);
    if (k == 2) p = sdm::Mesh::Point(p[0], -p[2], p[1]);
    if (k == 3) p *= 1.7;
    if (k >= 4)
      for (int c = 0; c < 3; ++c) {
        seed = seed * 1664525u + 1013904223u;
        p[c] += (k == 4 ? 1e-6 : 1e-7) * diag * (double(seed >> 8) / double(1u << 24) - 0.5);
      }
    m.set_point(v, p);
  }
  const std::string file = dir / (std::string("target.") + (k == 1 ? "obj" : k == 0 ? "ply" : "off"));
  sdm::write_mesh(m, file);
  if (const char* dump = std::getenv("SDM_TEST_DUMP"))  // the target too, to run sdm transfer on by hand
    std::filesystem::copy_file(file, std::string(dump) + "/variant_" + std::to_string(k) + "_" + std::filesystem::path(file).filename().string(),
                               std::filesystem::copy_options::overwrite_existing);
  return file;
}

// The bands of src onto variant k of tgt, each >= 90 % on its part; returns sdm transfer's output.
std::string check_variant(const Body& src, const Body& tgt, int k) {
  if (!faust::have(src.file) || !faust::have(tgt.file)) {
    WARN("no " << src.file << " or " << tgt.file << " at " << faust::humans_dir() << ": skipped");
    return "";
  }
  test_util::TempDir dir;
  const Bands r = transfer_bands(src, tgt, write_variant(sdm::load_mesh(faust::humans_dir() + "/" + tgt.file).mesh, k, dir));
  INFO(r.output);
  REQUIRE(r.exit_code == 0);
  std::fprintf(stderr, "%s -> %s (variant %d):\n%s", src.file, tgt.file, k, describe(r).c_str());
  for (int q = 0; q < 5; ++q) {
    INFO(kPart[q]);
    CHECK(r.on_part[q] >= 0.9);
  }
  return r.output;
}

}  // namespace

// Every coordinate of 024 moved by up to 1e-7 of the diagonal: its extraction then hangs the other
// arm from the upper of its two shoulder junctions, and before exchanged_branches every candidate
// match crossed the arms (both hands' bands on the wrong hand, 0 %).
TEST_CASE("sdm transfer: FAUST 007 onto 024 moved in the last bits keeps left and right", "[transfer_bands]") {
  check_variant(kBodies[0], kBodies[1], 5);
}

// 085 scaled by 1.7: its kept (medial) skeleton has no head end, the contraction candidate has one.
// Refused before TransferOptions::other_candidate; with it and the twist-only choice, mirrored
// (every hand and foot band on the other side, 0 %).
TEST_CASE("sdm transfer: FAUST 007 onto 085 scaled takes the target's other skeleton candidate", "[transfer_bands]") {
  const std::string output = check_variant(kBodies[0], kBodies[2], 3);
  if (output.find("registered with the other candidate of the target") == std::string::npos)
    WARN("the kept skeletons agreed this time: the other candidate was not needed");
}

// Both 007 and 085 moved by up to 1e-7 of their diagonals: the match that turns parts least is a
// mirror of 085 (every hand and foot band on the other side), and the right one fits 1.6 % closer and
// turns parts 0.4 % more; neither measure tells them apart. Either the bands land right or the
// command refuses, naming the tie: never the silent mirror it wrote before.
TEST_CASE("sdm transfer: a tie between left and right is refused, not guessed", "[transfer_bands]") {
  if (!faust::have(kBodies[0].file) || !faust::have(kBodies[2].file)) return;
  test_util::TempDir dir;
  check_right_or_refused(
      transfer_bands(kBodies[0], kBodies[2], write_variant(sdm::load_mesh(faust::humans_dir() + "/" + kBodies[2].file).mesh, 6, dir), 101),
      "cannot be told apart", "--match");
}

// The pairs above with the target written otherwise or moved (hidden: run with [bands_variants]),
// variants 0-4 of write_variant; SDM_BANDS_JITTERS=N runs variants 5 to 4 + N instead,
// SDM_BANDS_PAIR=i one pair of {007->024, 024->007, 007->085, gorilla->man, man->gorilla},
// SDM_BANDS_FROM=k from variant k on, SDM_BANDS_SOURCE_JITTER=SEED the source moved by up to 1e-7
// of its diagonal as well; SDM_TEST_DUMP=DIR keeps the painted sources and the targets there.
TEST_CASE("band transfer with the target written otherwise or moved, measured", "[.][bands_variants]") {
  std::vector<std::pair<int, int>> pairs = {{0, 1}, {1, 0}, {0, 2}, {3, 4}, {4, 3}};
  if (const char* only = std::getenv("SDM_BANDS_PAIR")) pairs = {pairs[size_t(std::atoi(only))]};
  const int jitters = std::getenv("SDM_BANDS_JITTERS") ? std::atoi(std::getenv("SDM_BANDS_JITTERS")) : 0;
  const int from = std::max(jitters ? 5 : 0, std::getenv("SDM_BANDS_FROM") ? std::atoi(std::getenv("SDM_BANDS_FROM")) : 0);
  int passed = 0, runs = 0;
  for (auto [s, t] : pairs) {
    if (!faust::have(kBodies[s].file) || !faust::have(kBodies[t].file)) continue;
    const sdm::Mesh b = sdm::load_mesh(faust::humans_dir() + "/" + kBodies[t].file).mesh;
    for (int k = from; k < (jitters ? 5 + jitters : 5); ++k) {
      test_util::TempDir dir;
      const char* seed = std::getenv("SDM_BANDS_SOURCE_JITTER");  // the source moved too
      const Bands r = transfer_bands(kBodies[s], kBodies[t], write_variant(b, k, dir), seed ? uint32_t(std::atoi(seed)) : 0);
      double worst = 1;
      for (int q = 0; q < 5; ++q) worst = std::min(worst, r.on_part[q]);
      ++runs, passed += r.exit_code == 0 && worst >= 0.9;
      std::fprintf(stderr, "%s -> %s (variant %d): exit %d, worst band %.1f %%\n", kBodies[s].file, kBodies[t].file, k, r.exit_code,
                   100 * worst);
      if (r.exit_code == 0 && worst < 0.9) std::fprintf(stderr, "%s", describe(r).c_str());
      if (r.exit_code != 0) std::fprintf(stderr, "%s\n", r.output.substr(r.output.rfind("error") == std::string::npos ? 0 : r.output.rfind("error")).c_str());
    }
  }
  std::fprintf(stderr, "%d of %d held\n", passed, runs);
}

// Every ordered pair of the five bodies (hidden: run with [bands_all]), each with its candidate
// matches' measures as `sdm transfer` reports them (the measures DECISIONS 5 chose the candidate
// score by).
TEST_CASE("band transfer on every pair of the five bodies, with the candidates, measured", "[.][bands_all]") {
  for (int s = 0; s < 5; ++s)
    for (int t = 0; t < 5; ++t) {
      if (s == t || !faust::have(kBodies[s].file) || !faust::have(kBodies[t].file)) continue;
      const Bands r = transfer_bands(kBodies[s], kBodies[t]);
      std::string cand;
      for (size_t at = 0; (at = r.output.find("candidate match ", at)) != std::string::npos;) {
        const size_t end = r.output.find('\n', at);
        cand += "    " + r.output.substr(at, end - at) + "\n";
        at = end;
      }
      double worst = 1;
      for (int k = 0; k < 5; ++k) worst = std::min(worst, r.on_part[k]);
      std::fprintf(stderr, "%s -> %s: exit %d, worst band %.1f %%\n%s%s", kBodies[s].file, kBodies[t].file, r.exit_code, 100 * worst,
                   cand.c_str(), r.exit_code == 0 ? describe(r).c_str() : "");
    }
}
