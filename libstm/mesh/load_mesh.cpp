#include "libstm/mesh/load_mesh.h"

#include "libstm/core/errors.h"
#include "libstm/mesh/drop_small_parts.h"

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
  const std::vector<std::string> lines = drop_small_soup_parts(soup, r.validation.speck_min_part);
  std::string named;  // every part, as --min-part names the parts it drops
  for (const auto& l : lines) named += (named.empty() ? "" : "; ") + l;
  r.repair.steps.push_back({"faces dropped: small parts beside the model, flat ones among them (no inside to map; parts under " +
                                number(r.validation.speck_min_part) + " of the diagonal)",
                            long(before - soup.triangles.size()), named});
  r.validation = validate_mesh(soup, &t);
}

}  // namespace

LoadReport repair_and_validate(MeshSoup& soup, const LoadOptions& options, EdgeTable* table) {
  LoadReport r;
  if (options.min_part > 0) r.dropped = drop_small_soup_parts(soup, options.min_part);
  EdgeTable scratch;
  EdgeTable& t = table ? *table : scratch;
  r.validation = validate_mesh(soup, &t);
  r.as_read = r.validation;
  if (options.repair && repair_may_help(r.validation)) {
    r.repair = repair_soup(soup, options.repair_options);
    if (r.repair.changed()) r.validation = validate_mesh(soup, &t);
    drop_flat_fragments(soup, r, t);
  }
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

Mesh load_mesh(const std::string& path, std::string* texture, std::vector<Eigen::Vector3f>* colors, Image* texture_image,
               double min_part, std::vector<std::string>* dropped) {
  LoadOptions options;
  options.min_part = min_part;
  LoadedMesh m = load_mesh(path, options);
  if (texture) *texture = std::move(m.texture);
  if (colors) *colors = std::move(m.colors);
  if (texture_image) *texture_image = std::move(m.texture_image);
  if (dropped) *dropped = std::move(m.report.dropped);
  return std::move(m.mesh);
}

std::vector<std::string> repair_lines(const RepairReport& report) {
  std::vector<std::string> lines;
  for (const auto& s : report.steps)
    lines.push_back("repaired: " + std::to_string(s.count) + " " + s.kind + (s.example.empty() ? "" : ", e.g. " + s.example));
  return lines;
}

}  // namespace sdm
