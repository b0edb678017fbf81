// sdm bench --transfer: texture transfer between different bodies, and the correspondence error on FAUST.
#include "apps/bench.h"
#include "apps/cli_common.h"
#include "apps/commands.h"
#include "apps/transfer_setup.h"
#include "libstm/core/errors.h"
#include "libstm/core/parallel.h"
#include "libstm/core/stopwatch.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/registration/correspondence_error.h"
#include "libstm/render/gl_context.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/transfer/transfer_texture.h"

#include <filesystem>
#include <iomanip>
#include <iostream>
#include <numeric>

namespace sdm::cli {
namespace {

struct TransferRow {
  std::string pair;
  int vertices = 0;
  double extract = INFINITY, transfer = INFINITY;  // seconds, fastest of the runs
  std::string kind;
  double rms = 0;
};

// The texture the bench's sources show (their uv a planar projection: with_planar_uv).
Image checker_texture() {
  Image checker(64, 64, 4, 255);
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) checker.pixels[4 * (64 * y + x)] = ((x / 8 + y / 8) % 2) ? 200 : 40;
  return checker;
}

// How the transfer found the target's skeleton, as `sdm transfer --json` names it.
std::string target_kind(const TextureTransfer& t) { return target_skeleton_name(t.kind, false); }

std::string pair_name(const std::string& a_path, const std::string& b_path) {
  return std::filesystem::path(a_path).stem().string() + " -> " + std::filesystem::path(b_path).stem().string();
}

// Both extractions, then transfer_texture (recognition, registration, layout, atlas, coordinates)
// with a 1024 atlas, as `sdm transfer` runs them; the fastest of `repeat` runs.
TransferRow time_transfer(GlContext& gl, const std::string& a_path, const std::string& b_path, int repeat) {
  const Mesh a = with_planar_uv(load_mesh(a_path).mesh), b = load_mesh(b_path).mesh;
  const Image checker = checker_texture();
  TransferRow row;
  row.pair = pair_name(a_path, b_path);
  row.vertices = int(a.n_vertices());
  TransferOptions to;
  to.size = 1024;
  for (int r = 0; r < repeat; ++r) {
    Stopwatch sw;
    Skeleton sa, sb;
    run_concurrently([&] { sb = extract_skeleton(b, transfer_skeleton_options()); }, [&] { sa = extract_skeleton(a, transfer_skeleton_options()); });
    const double e = sw.lap();
    const TextureTransfer t = transfer_texture(gl, a, checker, sa, b, sb, to);
    row.extract = std::min(row.extract, e), row.transfer = std::min(row.transfer, sw.lap());
    row.kind = target_kind(t);
    row.rms = t.fit_rms;
  }
  return row;
}

// ---- Correspondence error on FAUST (docs/BENCHMARKS.md) ----

// The FAUST registrations compared: one connectivity, so target vertex i truly shows source vertex
// i; 001 and 007 are one person in two poses.
const char* const kFaust[] = {"tr_reg_001.off", "tr_reg_007.off", "tr_reg_010.off", "tr_reg_024.off"};

// Mean geodesic errors on FAUST as published (x100 of sqrt(area), Kim et al. 2011's unit; the
// remeshed FAUST test pairs), beside ours.
struct PublishedError {
  const char* method;
  double mean;
};
const PublishedError kPublished[] = {{"BCICP", 6.1}, {"ZoomOut", 6.1}, {"Smooth Shells", 2.5}, {"Deep Shells", 1.7}, {"ULRSSM", 1.6}};

struct CorrespondenceRow {
  std::string pair, kind;
  std::string failure;  // why there is no correspondence (the transfer refused the pair), or empty
  double fit_rms = INFINITY, seconds = 0, measure_seconds = 0;
  double geodesic_mean = 0, geodesic_p90 = 0, euclidean_mean = 0, euclidean_p90 = 0;
};

// The ordered pair a -> b through what `sdm transfer` runs with its defaults (the meshes loaded as
// it loads them, both skeletons as it obtains them, its TransferOptions: 2048 atlas, the other
// extraction candidates), the source given a planar uv and a checker texture (neither reaches the
// correspondence), then every target vertex's error against the ground truth (correspondence_error).
// `seconds`: loading, both skeletons and the transfer, once; `measure_seconds`: the error.
// With `turned_scaled` the target is turned 180 degrees about its vertical (y) axis and scaled by 1.7
// once loaded; with `no_refine` the transfer keeps the registration's closest points (--no-refine).
CorrespondenceRow transfer_correspondence(GlContext& gl, const std::string& a_path, const std::string& b_path, bool turned_scaled,
                                          bool no_refine) {
  CorrespondenceRow row;
  row.pair = pair_name(a_path, b_path);
  Stopwatch sw;
  try {
    const Mesh a = with_planar_uv(load_mesh_min_part(a_path));
    Mesh b = load_mesh_min_part(b_path);
    if (turned_scaled)
      for (auto v : b.vertices()) {
        const Mesh::Point p = b.point(v);
        b.set_point(v, 1.7 * Mesh::Point(-p[0], p[1], -p[2]));
      }
    Skeleton sa, sb;
    SkeletonStats stats_a, stats_b;
    obtain_both_skeletons(
        a.n_vertices() + b.n_vertices(), [&] { sa = skeleton_for(a, "", "source", &stats_a, nullptr); },
        [&] { sb = skeleton_for(b, "", "target", &stats_b, nullptr); });
    TransferSettings settings;
    settings.no_refine = no_refine;
    const TransferOptions to = transfer_command_options(settings, a, b, stats_a, stats_b, nullptr);
    const TextureTransfer t = transfer_texture(gl, a, checker_texture(), sa, b, sb, to);
    row.seconds = sw.lap();
    row.kind = target_kind(t), row.fit_rms = t.fit_rms;
    if (a.n_vertices() != b.n_vertices() || t.correspondence.size() != b.n_vertices()) {
      row.failure = "no point correspondence of every target vertex";
      return row;
    }
    std::vector<int> truth(b.n_vertices());
    std::iota(truth.begin(), truth.end(), 0);
    const CorrespondenceError e = correspondence_error(a, t.correspondence, truth);
    row.measure_seconds = sw.lap();
    row.geodesic_mean = e.geodesic_mean, row.geodesic_p90 = e.geodesic_p90;
    row.euclidean_mean = e.euclidean_mean, row.euclidean_p90 = e.euclidean_p90;
  } catch (const InputError& e) {
    row.seconds = sw.lap();
    row.failure = e.what();
  }
  return row;
}

// Every ordered pair of kFaust found in `humans` (none, with a note, when one is missing).
std::vector<CorrespondenceRow> faust_correspondences(GlContext& gl, const std::string& humans, bool turned_scaled, bool no_refine) {
  std::vector<CorrespondenceRow> rows;
  for (const char* name : kFaust)
    if (!std::filesystem::exists(humans + "/" + name)) {
      std::cerr << "bench: " << humans << "/" << name << " missing: the FAUST correspondence error skipped\n";
      return rows;
    }
  const int n = int(std::size(kFaust));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (i == j) continue;
      std::cerr << "bench: correspondence " << kFaust[i] << " -> " << kFaust[j] << " (" << rows.size() + 1 << " of " << n * (n - 1) << ")\n";
      rows.push_back(transfer_correspondence(gl, humans + "/" + kFaust[i], humans + "/" + kFaust[j], turned_scaled, no_refine));
      const CorrespondenceRow& r = rows.back();
      if (!r.failure.empty()) std::cerr << "  refused: " << r.failure << "\n";
      else std::cerr << "  geodesic error mean " << r.geodesic_mean << ", p90 " << r.geodesic_p90 << " (" << r.seconds << " s)\n";
    }
  return rows;
}

// Over the pairs with a correspondence: the mean of their means, the worst mean and the worst p90.
struct CorrespondenceSummary {
  int measured = 0, refused = 0;
  double mean = 0, euclidean_mean = 0, worst_mean = 0, worst_p90 = 0;
  std::string worst_mean_pair, worst_p90_pair;
};

CorrespondenceSummary summarise(const std::vector<CorrespondenceRow>& rows) {
  CorrespondenceSummary s;
  for (const auto& r : rows) {
    if (!r.failure.empty()) {
      ++s.refused;
      continue;
    }
    ++s.measured;
    s.mean += r.geodesic_mean, s.euclidean_mean += r.euclidean_mean;
    if (r.geodesic_mean > s.worst_mean) s.worst_mean = r.geodesic_mean, s.worst_mean_pair = r.pair;
    if (r.geodesic_p90 > s.worst_p90) s.worst_p90 = r.geodesic_p90, s.worst_p90_pair = r.pair;
  }
  if (s.measured) s.mean /= s.measured, s.euclidean_mean /= s.measured;
  return s;
}

nlohmann::json correspondence_json(const std::vector<CorrespondenceRow>& rows) {
  nlohmann::json pairs = nlohmann::json::array(), published = nlohmann::json::object();
  for (const auto& r : rows) {
    nlohmann::json j = {{"pair", r.pair}, {"transfer_s", r.seconds}};
    if (!r.failure.empty()) {
      j["refused"] = r.failure;
    } else {
      j.update({{"target_skeleton", r.kind}, {"fit_rms", r.fit_rms}, {"geodesic_mean", r.geodesic_mean}, {"geodesic_p90", r.geodesic_p90},
                {"euclidean_mean_percent", r.euclidean_mean}, {"euclidean_p90_percent", r.euclidean_p90}, {"error_s", r.measure_seconds}});
    }
    pairs.push_back(j);
  }
  for (const auto& p : kPublished) published[p.method] = p.mean;
  const CorrespondenceSummary s = summarise(rows);
  return {{"unit", "geodesic distance on the source / sqrt(source area) x 100 (shortest paths through 5 points per edge and straight across faces: an upper bound, about 1 % over the exact geodesic on FAUST); euclidean in % of the "
                   "source's bounding-box diagonal"},
          {"pairs", pairs},
          {"measured", s.measured},
          {"refused", s.refused},
          {"geodesic_mean", s.mean},
          {"euclidean_mean_percent", s.euclidean_mean},
          {"worst_mean", s.worst_mean},
          {"worst_mean_pair", s.worst_mean_pair},
          {"worst_p90", s.worst_p90},
          {"worst_p90_pair", s.worst_p90_pair},
          {"published_faust_means", published}};
}

void print_correspondence_table(const std::vector<CorrespondenceRow>& rows, bool turned_scaled, bool no_refine) {
  std::cout << "\nCorrespondence error on FAUST (every ordered pair; `sdm transfer`'s defaults"
            << (no_refine ? " with --no-refine" : "") << (turned_scaled ? "; each target turned 180 degrees about y and scaled 1.7" : "")
            << "; geodesic on the source / sqrt(area) x 100,\n"
               "shortest paths through 5 points per edge (an upper bound), every target vertex; euclidean % of the diagonal; "
            << machine_line() << ")\n"
            << "| pair | target | fit RMS | geodesic mean | geodesic p90 | euclidean mean | euclidean p90 | transfer (s) | error (s) |\n"
            << "|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows) {
    std::cout << "| " << r.pair << " | ";
    if (!r.failure.empty()) {
      std::cout << "refused: " << r.failure << " | | | | | | " << std::fixed << std::setprecision(2) << r.seconds << " | |\n";
      continue;
    }
    std::cout << r.kind << " | " << std::fixed << std::setprecision(3) << 100 * r.fit_rms << " % | " << std::setprecision(2)
              << r.geodesic_mean << " | " << r.geodesic_p90 << " | " << r.euclidean_mean << " % | " << r.euclidean_p90 << " % | "
              << r.seconds << " | " << std::setprecision(3) << r.measure_seconds << " |\n";
  }
  const CorrespondenceSummary s = summarise(rows);
  std::cout << "Over the " << s.measured << " pairs measured (" << s.refused << " refused): geodesic mean " << std::setprecision(2) << s.mean
            << " (euclidean " << s.euclidean_mean << " %), worst mean " << s.worst_mean << " (" << s.worst_mean_pair << "), worst p90 "
            << s.worst_p90 << " (" << s.worst_p90_pair << ")\n"
            << "Published mean geodesic errors on FAUST (remeshed test pairs, the same unit):" << std::setprecision(1);
  const char* separator = " ";
  for (const auto& p : kPublished) std::cout << separator << p.method << " " << p.mean, separator = ", ";
  std::cout << "\n";
}

}  // namespace

int run_transfer_bench(const BenchOptions& o) {
  const std::vector<std::pair<std::string, std::string>> pairs{
      {"tr_reg_007.off", "tr_reg_024.off"}, {"tr_reg_024.off", "tr_reg_007.off"}, {"8_gorilla_01.off", "8_man_02.off"}};
  GlContext gl;
  std::vector<TransferRow> rows;
  for (const auto& [a, b] : pairs) {
    const std::string pa = o.humans + "/" + a, pb = o.humans + "/" + b;
    if (!std::filesystem::exists(pa) || !std::filesystem::exists(pb)) {
      std::cerr << "bench: " << pa << " or " << pb << " missing: skipped\n";
      continue;
    }
    std::cerr << "bench: transfer " << a << " -> " << b << "\n";
    rows.push_back(time_transfer(gl, pa, pb, o.repeat));
  }
  const std::vector<CorrespondenceRow> faust = faust_correspondences(gl, o.humans, o.turned_scaled, o.no_refine);
  if (o.json) {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& r : rows)
      j.push_back({{"pair", r.pair}, {"vertices", r.vertices}, {"extract_s", r.extract}, {"transfer_s", r.transfer},
                   {"total_s", r.extract + r.transfer}, {"target_skeleton", r.kind}, {"fit_rms", r.rms}});
    print_json({{"machine", machine_line()}, {"transfers", j}, {"faust_correspondence", correspondence_json(faust)},
                {"targets_turned_scaled", o.turned_scaled}, {"refined", !o.no_refine}});
    return 0;
  }
  std::cout << "Texture transfer between different bodies (1024 atlas; fastest of " << o.repeat << "; " << machine_line() << ")\n"
            << "| pair | vertices | both skeletons (s) | transfer (s) | total (s) | target | fit RMS |\n|---|---|---|---|---|---|---|\n";
  for (const auto& r : rows)
    std::cout << "| " << r.pair << " | " << r.vertices << " | " << std::fixed << std::setprecision(2) << r.extract << " | " << r.transfer
              << " | " << r.extract + r.transfer << " | " << r.kind << " | " << std::setprecision(3) << 100 * r.rms << " % |\n";
  if (!faust.empty()) print_correspondence_table(faust, o.turned_scaled, o.no_refine);
  return 0;
}

}  // namespace sdm::cli
