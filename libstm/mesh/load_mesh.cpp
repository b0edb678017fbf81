#include "libstm/mesh/load_mesh.h"

#include "libstm/core/errors.h"
#include "libstm/core/stopwatch.h"
#include "libstm/mesh/drop_small_parts.h"

#include <algorithm>

namespace sdm {

bool repair_may_help(const MeshReport& report) {
  if (!report.usable() || report.boundary_loops > 0) return true;
  for (const auto& f : report.findings)
    if (f.kind == "duplicated faces") return true;
  return false;
}

namespace {

// Whether the report's only fatal findings are flat parts.
bool only_flat_parts_refused(const MeshReport& report) {
  for (const auto& f : report.findings)
    if (f.fatal && f.kind.rfind("parts enclosing no volume", 0) != 0) return false;
  return !report.usable();
}

// Flat fragments beside a solid model (a face or two a non-manifold split left apart, a stray
// triangle): no capsule sees a flat part from inside, so they are dropped, each named, when every
// flat part is far smaller than the solid ones (validation's speck_min_part, the --min-part its
// refusal would suggest); anything larger keeps the refusal.
void drop_flat_fragments(MeshSoup& soup, LoadReport& r, EdgeTable& t) {
  if (!only_flat_parts_refused(r.validation) || !(r.validation.speck_min_part > 0)) return;
  const size_t before = soup.triangles.size();
  std::vector<int> kept;
  const std::vector<std::string> lines = drop_small_soup_parts(soup, r.validation.speck_min_part, &kept);
  if (lines.empty()) return;
  if (r.repair.face_source.size() == before)
    for (int& f : kept) f = r.repair.face_source[size_t(f)];
  r.repair.face_source = std::move(kept);
  std::string named;  // every part, as --min-part names the parts it drops
  for (const auto& l : lines) named += (named.empty() ? "" : "; ") + l;
  r.repair.steps.push_back({"faces dropped: small parts beside the model, flat ones among them (no inside to map; parts under " +
                                number(r.validation.speck_min_part) + " of the diagonal)",
                            long(before - soup.triangles.size()), named});
  r.validation = validate_mesh(soup, &t);
}

}  // namespace

namespace {

long finding_count(const MeshReport& r, const std::string& kind) {
  for (const auto& f : r.findings)
    if (f.kind == kind) return f.count;
  return 0;
}

}  // namespace

RepairHints repair_hints(const TopologyScan& scan) {
  RepairHints h;
  h.table = std::find(scan.face_ok.begin(), scan.face_ok.end(), char(0)) == scan.face_ok.end() ? &scan.table : nullptr;
  h.borders = finding_count(scan.report, "boundary edges (the mesh is open)") > 0;
  h.crowded_or_inconsistent = finding_count(scan.report, "non-manifold edges") + finding_count(scan.report, "edges between inconsistently oriented faces") > 0;
  h.duplicated = false;  // not scanned: every duplicate but a back-to-back pair makes an edge crowded or inconsistent
  h.pinched = &scan.nonmanifold_vertices;
  return h;
}

namespace {

// `then`, a repair of the soup `first` left, folded into `first`.
void fold_repair(RepairReport& first, RepairReport&& then) {
  for (auto& s : then.steps) {
    auto same = std::find_if(first.steps.begin(), first.steps.end(), [&](const RepairStep& x) { return x.kind == s.kind; });
    if (same != first.steps.end()) same->count += s.count;
    else first.steps.push_back(std::move(s));
  }
  for (int& f : then.face_source) f = first.face_source[size_t(f)];
  for (int& p : then.point_source) p = first.point_source[size_t(p)];
  first.face_source = std::move(then.face_source), first.point_source = std::move(then.point_source);
}

// Repair with `hints`, validation of the result (when it changed) and, where that still finds what
// a repair mends (the back-to-back duplicates the scan does not look for), one more repair.
void repair_then_validate(MeshSoup& soup, const LoadOptions& options, const RepairHints& hints, LoadReport& r, EdgeTable& t) {
  Stopwatch sw;
  r.repair = repair_soup(soup, options.repair_options, hints);
  r.repair_seconds = sw.lap();
  if (!r.repair.changed()) return;
  r.validation = validate_mesh(soup, &t);
  if (r.validation.usable() || finding_count(r.validation, "duplicated faces") == 0) return;
  RepairHints again;
  again.table = t.edges() ? &t : nullptr, again.borders = r.validation.boundary_loops > 0;
  sw.restart();
  fold_repair(r.repair, repair_soup(soup, options.repair_options, again));
  r.repair_seconds += sw.lap();
  r.validation = validate_mesh(soup, &t);
}

}  // namespace

LoadReport repair_and_validate(MeshSoup& soup, const LoadOptions& options, EdgeTable* table) {
  LoadReport r;
  if (options.min_part > 0) r.dropped = drop_small_soup_parts(soup, options.min_part);
  EdgeTable scratch;
  EdgeTable& t = table ? *table : scratch;
  if (options.repair && !options.report_as_read && soup.points.size() > 2 * soup.triangles.size() && !soup.triangles.empty()) {
    // More points than twice the faces (a closed mesh has half as many points as faces): a soup,
    // repaired (welded) before anything is measured of it, as a scan of the unwelded soup only
    // says that every edge is a border (a 450k-vertex mesh as a soup: 1.03 -> 0.83 s).
    r.as_read.vertices = long(soup.points.size()), r.as_read.faces = long(soup.triangles.size());
    RepairHints everywhere;
    repair_then_validate(soup, options, everywhere, r, t);
    if (!r.repair.changed()) r.validation = validate_mesh(soup, &t);
    drop_flat_fragments(soup, r, t);
    return r;
  }
  TopologyScan scan = scan_topology(soup);
  if (options.repair && !options.report_as_read && scan.repair_needed()) {
    // Repair from the scan alone: the rest of validation is measured once, on the repaired soup.
    r.as_read = scan.report;
    repair_then_validate(soup, options, repair_hints(scan), r, t);
    if (!r.repair.changed()) r.validation = finish_validation(soup, std::move(scan), &t);
  } else {
    RepairHints hints = repair_hints(scan);
    r.validation = finish_validation(soup, std::move(scan), &t);
    r.as_read = r.validation;
    hints.table = t.edges() ? &t : nullptr, hints.duplicated = finding_count(r.validation, "duplicated faces") > 0;
    if (options.repair && repair_may_help(r.validation)) repair_then_validate(soup, options, hints, r, t);
  }
  if (options.repair) drop_flat_fragments(soup, r, t);
  return r;
}

LoadReport prepare_soup(MeshSoup& soup, const std::string& what, const LoadOptions& options, EdgeTable* table) {
  EdgeTable scratch;
  EdgeTable& t = table ? *table : scratch;
  LoadReport r = repair_and_validate(soup, options, &t);
  if (!r.validation.usable()) throw InputError(r.validation.refusal(what));
  if (orient_outward(soup, r.validation) > 0) t = EdgeTable();  // its sides' directions changed
  return r;
}

LoadedMesh load_mesh(const std::string& path, const LoadOptions& options) {
  MeshSoup soup = read_mesh_soup(path);
  LoadedMesh out;
  EdgeTable table;
  out.report = prepare_soup(soup, path, options, &table);
  out.texture = soup.texture;
  out.texture_image = std::move(soup.texture_image);
  if (!soup.colors.empty()) {
    const std::vector<char> used = used_points(soup);
    for (size_t i = 0; i < soup.colors.size(); ++i)
      if (used[i]) out.colors.push_back(soup.colors[i]);
  }
  out.mesh = build_mesh(soup, table.edges() ? &table : nullptr);
  return out;
}

std::vector<std::string> repair_lines(const RepairReport& report) {
  std::vector<std::string> lines;
  for (const auto& s : report.steps)
    lines.push_back("repaired: " + std::to_string(s.count) + " " + s.kind + (s.example.empty() ? "" : ", e.g. " + s.example));
  return lines;
}

}  // namespace sdm
