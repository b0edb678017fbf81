// Texture transfer's correspondence between different bodies (register_bodies), as `sdm transfer`
// computes it, from the extracted skeletons with no key given, measured against the FAUST ground
// truth (tr_reg_007 and tr_reg_024: vertex i corresponds to vertex i): the distance between the
// source point each target vertex gets and its true source point, in % of the diagonal.
#include "faust_diagnostics.h"
#include "faust_pairs.h"

#include "test_util.h"

#include "libstm/core/errors.h"
#include "libstm/core/image.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/primitives.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/correspondence/end_bends.h"
#include "libstm/correspondence/register_bodies.h"
#include "libstm/transfer/transfer_texture.h"

#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <fstream>
#include <sstream>

namespace {

struct Measured {
  faust::Error error;
  double rms = 0, p99 = 0;
  std::string text;
};

Measured measure(const std::string& name, const sdm::Mesh& a, const sdm::Skeleton& sa, const sdm::Mesh& b) {
  const sdm::Skeleton sb = sdm::extract_skeleton(b, sdm::transfer_skeleton_options());
  const sdm::BodyRegistration r = sdm::register_bodies(a, sa, b, sb, {});
  Measured m;
  m.error = faust::correspondence_error(a, sdm::source_points_under(a, r.placed, faust::points_of(b)));
  m.rms = r.rms, m.p99 = r.p99;
  std::ostringstream o;
  o.precision(3);
  if (std::getenv("SDM_MEASURE_PARTS")) diagnose::print_chain_errors(a, b, r);
  if (const char* prefix = std::getenv("SDM_MEASURE_COLOURS")) diagnose::write_error_colors(a, b, r, prefix);
  if (std::getenv("SDM_MEASURE_ROTATIONS")) diagnose::print_rotation_errors(a, b, r);
  o << name << ": fit RMS " << 100 * r.rms << " %, p99 " << 100 * r.p99 << " %; correspondence mean " << m.error.mean << " %, p90 "
    << m.error.p90 << " %, beyond 5 %: " << m.error.beyond5 << " % of the vertices";
  m.text = o.str();
  return m;
}

}  // namespace

// Measured (Release): 007 -> 024 mean 2.05 %, p90 4.1 %, 5.5 % of the vertices beyond 5 %, fit RMS
// 0.27 %; with the arm bent 2.05 %, 4.5 %, 6.5 % (2.7 %, 5.6 %, 15 % before the length filter of the
// candidate matches and the slides of common_branching); 024 -> 007 2.3 %, 5.7 %, 13 %, turned and scaled 2.5 %,
// 5.8 %, 16 % (the match with left and right swapped, chosen without the registration's twist, gave
// 22 %). 007 -> 024 turned and scaled, and 024 -> 007 with the arm bent, pass since 2026-11-26 (the
// extraction still changes under a 1e-7 relative perturbation of the coordinates: DECISIONS 5; where
// the error is: [faust_measure] with SDM_MEASURE_PARTS, SDM_MEASURE_COLOURS=PREFIX,
// SDM_MEASURE_ROTATIONS). The target is 1 %, 2.5 % and
// 1 %: the thresholds hold what is reached, with a margin (before register_bodies, the transfer
// matched the extracted skeletons and put 007 -> 024 6.4 % off, 024 -> 007 19.2 %).
TEST_CASE("register_bodies: FAUST 007 onto 024 from the extracted skeletons", "[register_bodies]") {
  if (!faust::have("tr_reg_007.off") || !faust::have("tr_reg_024.off")) {
    WARN("no FAUST meshes at " << faust::humans_dir() << ": skipped");
    return;
  }
  const sdm::Mesh a = sdm::load_mesh(faust::humans_dir() + "/tr_reg_007.off").mesh;
  const sdm::Mesh b = sdm::load_mesh(faust::humans_dir() + "/tr_reg_024.off").mesh;
  const sdm::Skeleton sa = sdm::extract_skeleton(a, sdm::transfer_skeleton_options());
  const Measured plain = measure("007 -> 024", a, sa, b);
  std::fprintf(stderr, "%s\n", plain.text.c_str());
  CHECK(plain.rms < 0.005);
  CHECK(plain.error.mean < 2.6);
  CHECK(plain.error.p90 < 5.0);
  CHECK(plain.error.beyond5 < 8);
  const Measured arm = measure("007 -> 024, an arm bent 90 degrees more", a, sa, faust::arm_bent(b, sa, 90));
  std::fprintf(stderr, "%s\n", arm.text.c_str());
  CHECK(arm.rms < 0.005);
  CHECK(arm.error.mean < 3.2);
  CHECK(arm.error.p90 < 6.5);
  CHECK(arm.error.beyond5 < 18);
  // Measured 2026-11-26: 1.87 %, 4.2 %, 4.7 % (the scaled target's skeleton used to split the head
  // into three prongs; it no longer does with today's extraction).
  const Measured turned = measure("007 -> 024 turned 180 degrees and scaled 1.7", a, sa, faust::turned_scaled(b, 1.7));
  std::fprintf(stderr, "%s\n", turned.text.c_str());
  CHECK(turned.rms < 0.005);
  CHECK(turned.error.mean < 2.6);
  CHECK(turned.error.p90 < 5.0);
  CHECK(turned.error.beyond5 < 8);
}

TEST_CASE("register_bodies: FAUST 024 onto 007 from the extracted skeletons", "[register_bodies]") {
  if (!faust::have("tr_reg_007.off") || !faust::have("tr_reg_024.off")) {
    WARN("no FAUST meshes at " << faust::humans_dir() << ": skipped");
    return;
  }
  const sdm::Mesh a = sdm::load_mesh(faust::humans_dir() + "/tr_reg_024.off").mesh;
  const sdm::Mesh b = sdm::load_mesh(faust::humans_dir() + "/tr_reg_007.off").mesh;
  const sdm::Skeleton sa = sdm::extract_skeleton(a, sdm::transfer_skeleton_options());
  const Measured plain = measure("024 -> 007", a, sa, b);
  std::fprintf(stderr, "%s\n", plain.text.c_str());
  CHECK(plain.rms < 0.005);
  CHECK(plain.error.mean < 2.9);
  CHECK(plain.error.p90 < 6.5);
  CHECK(plain.error.beyond5 < 16);
  const Measured turned = measure("024 -> 007 turned 180 degrees and scaled 1.7", a, sa, faust::turned_scaled(b, 1.7));
  std::fprintf(stderr, "%s\n", turned.text.c_str());
  CHECK(turned.rms < 0.005);
  CHECK(turned.error.mean < 2.9);
  CHECK(turned.error.p90 < 6.5);
  CHECK(turned.error.beyond5 < 19);
  // Measured 2026-11-26: 2.71 %, 5.5 %, 13.9 % (refused before: the bent target's skeleton joined
  // its branches otherwise).
  const Measured arm = measure("024 -> 007, an arm bent 90 degrees more", a, sa, faust::arm_bent(b, sa, 90));
  std::fprintf(stderr, "%s\n", arm.text.c_str());
  CHECK(arm.rms < 0.005);
  CHECK(arm.error.mean < 3.2);
  CHECK(arm.error.p90 < 6.5);
  CHECK(arm.error.beyond5 < 18);
}

TEST_CASE("register_bodies refuses branchings that differ beyond small branches", "[register_bodies]") {
  const sdm::Mesh a = sdm::make_primitive("ypsilon", 1500);
  const sdm::Mesh b = sdm::make_primitive("crossed-cylinders", 1500);
  const sdm::Skeleton sa = sdm::extract_skeleton(a, sdm::transfer_skeleton_options());
  const sdm::Skeleton sb = sdm::extract_skeleton(b, sdm::transfer_skeleton_options());
  CHECK_THROWS_AS(sdm::register_bodies(a, sa, b, sb, {}), sdm::InputError);
}

// The command as a user runs it: a textured FAUST 007 onto 024; the correspondence file read back
// gives the same error as the library (each line: source face and barycentric coordinates).
TEST_CASE("sdm transfer --correspondence between two FAUST bodies", "[register_bodies]") {
  if (!faust::have("tr_reg_007.off") || !faust::have("tr_reg_024.off")) {
    WARN("no FAUST meshes at " << faust::humans_dir() << ": skipped");
    return;
  }
  test_util::TempDir dir;
  const sdm::Mesh a = faust::write_textured("tr_reg_007.off", dir / "a.obj", dir / "a.png");
  const std::string target = faust::humans_dir() + "/tr_reg_024.off";
  const auto res = test_util::run_sdm("transfer --source " + (dir / "a.obj") + " --target " + target + " -o " + (dir / "b.obj") +
                                      " --size 256 --correspondence " + (dir / "c.txt") + " --json");
  INFO(res.output);
  REQUIRE(res.exit_code == 0);
  const auto j = nlohmann::json::parse(res.output.substr(res.output.find("{\n")));
  CHECK(j.at("target_skeleton") == "registered");
  CHECK(j.at("fit_rms").get<double>() < 0.005);
  CHECK(j.at("branch_fit").size() >= 5);
  // Each candidate's measures, how alike its ends bend among them (the right match: 1.32).
  const auto bends = j.at("candidate_bend").get<std::vector<double>>();
  CHECK(bends.size() == j.at("candidate_twist").size());
  CHECK(*std::max_element(bends.begin(), bends.end()) > 1.0);
  const std::vector<sdm::SourcePoint> under = faust::read_correspondence(dir / "c.txt");
  for (const sdm::SourcePoint& p : under) CHECK(std::abs(p.barycentric.sum() - 1) < 1e-6);
  REQUIRE(under.size() == a.n_vertices());
  const faust::Error e = faust::correspondence_error(a, under);
  INFO("mean " << e.mean << " %, p90 " << e.p90 << " %");
  CHECK(e.mean < 2.6);
  CHECK(e.p90 < 5.0);
  // A correspondence file of another kind is refused before any work, and nothing is written.
  const auto bad = test_util::run_sdm("transfer --source " + (dir / "a.obj") + " --target " + target + " -o " + (dir / "d.obj") +
                                      " --correspondence " + (dir / "c.bin"));
  CHECK(bad.exit_code == 2);
  CHECK(bad.output.find(".txt or .json") != std::string::npos);
  CHECK(!std::filesystem::exists(dir / "d.obj"));
}

// Which candidate match the short registration would choose, against the ground truth (hidden:
// run with [candidates_measure]); see DECISIONS 5, "Registering other bodies".
#include "libstm/registration/articulated_registration.h"
TEST_CASE("register_bodies: candidate matches against the FAUST ground truth", "[.][candidates_measure]") {
  if (!faust::have("tr_reg_007.off") || !faust::have("tr_reg_024.off")) return;
  for (int dir = 0; dir < (std::getenv("DIR0") ? 1 : 2); ++dir) {
    const sdm::Mesh a = sdm::load_mesh(faust::humans_dir() + (dir ? "/tr_reg_024.off" : "/tr_reg_007.off")).mesh;
    const sdm::Mesh b0 = sdm::load_mesh(faust::humans_dir() + (dir ? "/tr_reg_007.off" : "/tr_reg_024.off")).mesh;
    const sdm::Skeleton sa = sdm::extract_skeleton(a, sdm::transfer_skeleton_options());
    for (int turned = std::getenv("TURNED") ? 1 : 0; turned < 2; ++turned) {
      const sdm::Mesh b = turned ? faust::turned_scaled(b0, 1.7) : b0;
      const sdm::Skeleton sb = sdm::extract_skeleton(b, sdm::transfer_skeleton_options());
      const auto cands = sdm::share_skeletons_candidates(a, sa, b, sb, {}, 2.0, std::getenv("CANDS") ? std::atoi(std::getenv("CANDS")) : 8);
      std::fprintf(stderr, "dir %d turned %d: pruned source ends %zu, target ends %zu; target skeleton %zu nodes\n", dir, turned, cands[0].pruned_a.size(), cands[0].pruned_b.size(), sb.nodes.size());
      {
        const auto adj = sb.adjacency();
        std::vector<double> own(sb.nodes.size(), 0);
        for (int n : sb.vertex_node) own[n] += 1;
        for (size_t k = 0; k < adj.size(); ++k)
          if (adj[k].size() != 2) std::fprintf(stderr, "  target key %zu deg %zu at %.2f %.2f %.2f owns %.0f%s\n", k, adj[k].size(), sb.nodes[k].x(), sb.nodes[k].y(), sb.nodes[k].z(), own[k],
                                               std::find(cands[0].pruned_b.begin(), cands[0].pruned_b.end(), int(k)) != cands[0].pruned_b.end() ? " PRUNED" : "");
      }
      const double diag = sdm::bounding_box_diagonal(b);
      for (size_t i = 0; i < cands.size(); ++i) {
        const auto truth = faust::true_guess(cands[i].a, b);
        double ge = 0;
        for (size_t k = 0; k < truth.size(); ++k) ge += (truth[k] - cands[i].b.nodes[k]).norm() / diag / truth.size();
        sdm::ArticulatedOptions q;
        q.iterations = 8, q.refine = false;
        const auto f = sdm::articulated_registration(a, cands[i].a, b, cands[i].b.nodes, q);
        q.iterations = 30;
        const auto f2 = sdm::articulated_registration(a, cands[i].a, b, cands[i].b.nodes, q);
        const auto e = faust::correspondence_error(a, sdm::source_points_under(a, f2.posed, faust::points_of(b)));
        for (const auto* ff : {&f, &f2}) {
          double twist = 0, worst = 0;
          for (const auto& ed : cands[i].a.edges) {
            const Eigen::Matrix3d D = ff->node_motion[ed[0]].rotation.transpose() * ff->node_motion[ed[1]].rotation;
            const double ang = std::acos(std::clamp((D.trace() - 1) / 2, -1.0, 1.0)) * 180 / M_PI;
            twist += ang, worst = std::max(worst, ang);
          }
          std::fprintf(stderr, "   relative rotations: mean %.1f deg, max %.0f deg\n", twist / cands[i].a.edges.size(), worst);
        }
        std::fprintf(stderr, "dir %d turned %d cand %zu: guess error %.2f %%, quick rms %.3f %%, full rms %.3f %%, corr mean %.2f %%\n", dir, turned, i, 100 * ge,
                     100 * f.posed_rms, 100 * f2.posed_rms, e.mean);
      }
    }
  }
}


// The FAUST ground-truth pairs in one run, with where the error is (hidden: run with
// [faust_measure]; DECISIONS 5 and BENCHMARKS quote it).
TEST_CASE("register_bodies: FAUST pairs measured", "[.][faust_measure]") {
  if (!faust::have("tr_reg_007.off") || !faust::have("tr_reg_024.off")) return;
  const sdm::Mesh m007 = sdm::load_mesh(faust::humans_dir() + "/tr_reg_007.off").mesh;
  const sdm::Mesh m024 = sdm::load_mesh(faust::humans_dir() + "/tr_reg_024.off").mesh;
  for (int dir = 0; dir < 2; ++dir) {
    const sdm::Mesh& a = dir ? m024 : m007;
    const sdm::Mesh& b = dir ? m007 : m024;
    const sdm::Skeleton sa = sdm::extract_skeleton(a, sdm::transfer_skeleton_options());
    const std::string name = dir ? "024 -> 007" : "007 -> 024";
    for (int variant = 0; variant < 3; ++variant) {
      try {
        const sdm::Mesh t = variant == 0 ? b : variant == 1 ? faust::turned_scaled(b, 1.7) : faust::arm_bent(b, sa, 90);
        const Measured m = measure(name + (variant == 1 ? " turned+scaled" : variant == 2 ? " arm bent" : ""), a, sa, t);
        std::fprintf(stderr, "%s\n", m.text.c_str());
      } catch (const std::exception& e) {
        std::fprintf(stderr, "%s variant %d: %s\n", name.c_str(), variant, e.what());
      }
    }
  }
}

// fit_skeleton's start_rotations, and how much of the error the start's rotations explain: FAUST
// 007 -> 024 with the match register_bodies chooses, fitted from each node's true rotation (Kabsch
// of its vertices onto their true places) instead of the smallest rotation of its edges. Measured
// 2026-11-26: 1.13 % mean, p90 2.43 %, 0.7 % beyond 5 % (rotations 8.9 degrees off after the fit)
// against 2.04 %, 4.18 %, 6.1 % (45 degrees off): the twist of the limbs is what is missing
// (DECISIONS 5).
TEST_CASE("fit_skeleton from the true node rotations: the bound a better start reaches", "[register_bodies]") {
  if (!faust::have("tr_reg_007.off") || !faust::have("tr_reg_024.off")) {
    WARN("no FAUST meshes at " << faust::humans_dir() << ": skipped");
    return;
  }
  const sdm::Mesh a = sdm::load_mesh(faust::humans_dir() + "/tr_reg_007.off").mesh;
  const sdm::Mesh b = sdm::load_mesh(faust::humans_dir() + "/tr_reg_024.off").mesh;
  const sdm::Skeleton sa = sdm::extract_skeleton(a, sdm::transfer_skeleton_options());
  const sdm::Skeleton sb = sdm::extract_skeleton(b, sdm::transfer_skeleton_options());
  const sdm::BodyRegistration r = sdm::register_bodies(a, sa, b, sb, {});
  std::vector<double> weight, owned(r.skeletons.a.nodes.size(), 0.0);
  const std::vector<Eigen::Matrix3d> truth = diagnose::true_rotations(a, b, r.skeletons.a, weight);
  for (int n : r.skeletons.a.vertex_node) owned[n] += 1;
  const sdm::Similarity start = sdm::fit_similarity(r.skeletons.a.nodes, r.skeletons.b.nodes, owned);
  sdm::FitSkeletonOptions fo;
  fo.stride = 2;
  fo.start_rotations = truth;
  const sdm::SkeletonFit fit = sdm::fit_skeleton(a, r.skeletons.a, b, start, r.skeletons.b.nodes, fo);
  const faust::Error from_truth = faust::correspondence_error(a, sdm::source_points_under(a, fit.bent, faust::points_of(b)));
  const faust::Error plain = faust::correspondence_error(a, sdm::source_points_under(a, r.placed, faust::points_of(b)));
  double off = 0, W = 0;
  for (size_t k = 0; k < truth.size(); ++k) off += weight[k] * diagnose::angle_between(fit.node_rotation[k], truth[k]), W += weight[k];
  std::fprintf(stderr, "from the true rotations: mean %.2f %%, p90 %.2f %%, beyond 5 %% %.1f %%, rotations %.1f degrees off after the fit\n",
               from_truth.mean, from_truth.p90, from_truth.beyond5, off / W);
  CHECK(from_truth.mean < 1.4);
  CHECK(from_truth.p90 < 3.0);
  CHECK(from_truth.beyond5 < 2.0);
  CHECK(from_truth.mean < 0.7 * plain.mean);
  CHECK(off / W < 15);  // the fit keeps a right start (it drifts 10-45 degrees from a wrong one)
  // A wrong-sized list is ignored: the default start.
  fo.start_rotations.pop_back();
  const sdm::SkeletonFit plain_fit = sdm::fit_skeleton(a, r.skeletons.a, b, start, r.skeletons.b.nodes, fo);
  const faust::Error e = faust::correspondence_error(a, sdm::source_points_under(a, plain_fit.bent, faust::points_of(b)));
  CHECK(std::abs(e.mean - plain.mean) < 0.05);
}

namespace {

// The end node of `s` nearest each of the given vertices of `mesh`.
std::vector<int> ends_nearest(const sdm::Mesh& mesh, const sdm::Skeleton& s, const std::vector<int>& vertices) {
  const auto adj = s.adjacency();
  std::vector<int> out;
  for (int v : vertices) {
    int best = -1;
    for (size_t n = 0; n < adj.size(); ++n)
      if (adj[n].size() == 1 &&
          (best < 0 || (s.nodes[n] - sdm::point(mesh, mesh.vertex_handle(v))).norm() < (s.nodes[best] - sdm::point(mesh, mesh.vertex_handle(v))).norm()))
        best = int(n);
    out.push_back(best);
  }
  return out;
}

}  // namespace

// The places where the limbs meet the torso (BodyRegistration::attachment, DECISIONS 5) see
// a match that crosses one pair of limbs and keeps the others, which twist and fit barely do: 007 ->
// 024 with the hands pinned crossed and the head and feet pinned straight lays them further apart
// than with every end pinned straight (which end is which from SMPL's vertex ids: the top of the
// head, the middle fingertips, the big toes).
TEST_CASE("register_bodies: crossed hands lay the limbs' attachments further apart", "[register_bodies]") {
  if (!faust::have("tr_reg_007.off") || !faust::have("tr_reg_024.off")) return;
  const sdm::Mesh a = sdm::load_mesh(faust::humans_dir() + "/tr_reg_007.off").mesh, b = sdm::load_mesh(faust::humans_dir() + "/tr_reg_024.off").mesh;
  const sdm::Skeleton sa = sdm::extract_skeleton(a, sdm::transfer_skeleton_options()), sb = sdm::extract_skeleton(b, sdm::transfer_skeleton_options());
  const std::vector<int> landmarks = {411, 2445, 5905, 3216, 6617};  // head, left hand, right hand, left foot, right foot
  const std::vector<int> ea = ends_nearest(a, sa, landmarks), eb = ends_nearest(b, sb, landmarks);
  std::vector<std::pair<int, int>> straight, crossed;
  for (int k = 0; k < 5; ++k) {
    straight.push_back({ea[k], eb[k]});
    crossed.push_back({ea[k], eb[k == 1 ? 2 : k == 2 ? 1 : k]});
  }
  const sdm::BodyRegistration right = sdm::register_bodies(a, sa, b, sb, straight);
  const sdm::BodyRegistration wrong = sdm::register_bodies(a, sa, b, sb, crossed);
  INFO("attachments " << 100 * right.attachment << " % straight, " << 100 * wrong.attachment << " % crossed; twist "
                      << right.candidate_twist[size_t(right.chosen)] << " / " << wrong.candidate_twist[size_t(wrong.chosen)] << " degrees");
  CHECK(right.attachment < 0.05);
  CHECK(wrong.attachment > 1.3 * right.attachment);
}

// The ends of two real bodies matched the right way bend alike (end_bend_agreement); with left and
// right swapped (hands and feet pinned to the other side, head kept) the match can only lay the core
// half around and the ends bend the other way, by more than register_bodies' margin (0.4). FAUST
// 007 onto 024 (another person, one leg raised) and the TOSCA gorilla onto the man.
TEST_CASE("register_bodies: a mirrored match's ends bend the other way", "[register_bodies]") {
  struct Pair {
    const char *a, *b;
    std::vector<int> la, lb;  // head, left hand, right hand, left foot, right foot
  };
  const Pair pairs[] = {{"tr_reg_007.off", "tr_reg_024.off", {411, 2445, 5905, 3216, 6617}, {411, 2445, 5905, 3216, 6617}},
                        {"8_gorilla_01.off", "8_man_02.off", {889, 3401, 2374, 4976, 4179}, {2982, 962, 228, 4617, 513}}};
  for (const Pair& p : pairs) {
    if (!faust::have(p.a) || !faust::have(p.b)) continue;
    const sdm::Mesh a = sdm::load_mesh(faust::humans_dir() + "/" + p.a).mesh, b = sdm::load_mesh(faust::humans_dir() + "/" + p.b).mesh;
    const sdm::Skeleton sa = sdm::extract_skeleton(a, sdm::transfer_skeleton_options()), sb = sdm::extract_skeleton(b, sdm::transfer_skeleton_options());
    const std::vector<int> ea = ends_nearest(a, sa, p.la), eb = ends_nearest(b, sb, p.lb);
    std::vector<std::pair<int, int>> straight, mirrored;
    const int other[5] = {0, 2, 1, 4, 3};
    for (int k = 0; k < 5; ++k) straight.push_back({ea[k], eb[k]}), mirrored.push_back({ea[k], eb[other[k]]});
    const sdm::SharedSkeletons s = sdm::share_skeletons(a, sa, b, sb, straight), m = sdm::share_skeletons(a, sa, b, sb, mirrored);
    const double right = sdm::end_bend_agreement(s.a, s.b), mirror = sdm::end_bend_agreement(m.a, m.b);
    INFO(p.a << " -> " << p.b << ": ends bend alike " << right << " matched straight, " << mirror << " mirrored");
    CHECK(right > 0.2);
    CHECK(right - mirror > 0.4);
  }
}
