#include "apps/encode_checks.h"

#include "apps/commands.h"
#include "apps/memory_budget.h"
#include "libstm/core/errors.h"

#include <cmath>
#include <sstream>

namespace sdm::cli {

std::string point_text(const Eigen::Vector3d& p) {
  std::ostringstream s;
  s << '(' << p.x() << ", " << p.y() << ", " << p.z() << ')';
  return s.str();
}

sdm::SelfIntersections check_self_intersections(const sdm::Mesh& mesh, bool strict) {
  const sdm::SelfIntersections x = sdm::find_self_intersections(sdm::vertex_matrix(mesh), sdm::face_matrix(mesh));
  if (x.pairs == 0) return x;
  const std::string what = "the surface intersects itself (" + std::to_string(x.pairs) + " pairs of faces cross, e.g. faces " +
                           std::to_string(x.face_a) + " and " + std::to_string(x.face_b) + " at " + point_text(x.example) + ")";
  const std::string fix = "a displacement map holds one surface per ray, so crossing sheets cannot both be kept: separate them "
                          "in a modelling tool (e.g. Blender's 3D-Print toolbox, 'Intersect Faces')";
  if (strict) throw sdm::InputError(what + "; " + fix);
  progress("warning: " + what + ": " + fix + " (--strict refuses such input)");
  return x;
}

namespace {

// Warns of (or, under --strict, refuses) a coverage under `floor`.
sdm::SurfaceCoverage carried_or_warn(const sdm::SurfaceCoverage& c, double diag, double floor, bool strict) {
  if (c.share >= floor) return c;
  std::ostringstream what;
  what << "the map carries only " << std::round(1000 * c.share) / 10 << " % of the surface within "
       << 100 * kCarriedTolerance << " % of the diagonal (at least " << 100 * floor << " % expected); the farthest point, "
       << point_text(c.worst_point) << ", is " << std::round(1000 * c.worst / diag) / 10 << " % of the diagonal away";
  const std::string fix = "try a larger --size, or check the input for sheets inside each other or parts the skeleton misses "
                          "('sdm skeleton --png')";
  if (strict) throw sdm::InputError(what.str() + "; " + fix);
  progress("warning: " + what.str() + ": " + fix + " (--strict refuses such output)");
  return c;
}

}  // namespace

sdm::SurfaceCoverage check_carried(const sdm::Mesh& input, const sdm::Mesh& decoded, double diag, double floor, bool strict) {
  return carried_or_warn(sdm::surface_coverage(input, decoded, kCarriedTolerance * diag), diag, floor, strict);
}

sdm::SurfaceCoverage check_carried(const sdm::Mesh& input, const sdm::DecodedSurface& decoded, double diag, double floor, bool strict) {
  return carried_or_warn(sdm::surface_coverage(input, sdm::point_matrix(decoded), decoded.triangles, kCarriedTolerance * diag), diag, floor, strict);
}

void add_face_error_option(CLI::App* app, double& error) {
  app->add_option("--face-error", error,
                  "Base faces that decode (level 3) farther than this fraction of the diagonal from the input are placed on their flat "
                  "triangle, or the base mesh is made finer there (0: no check)")
      ->capture_default_str()
      ->check(number_in(0.0, 1.0));
}

void encode_check_options(sdm::EncodeOptions& eo, double face_error) {
  eo.flat_above = face_error;
  eo.refine_above = 3 * face_error;
}

void add_min_carried_option(CLI::App* app, double& floor) {
  app->add_option("--min-carried", floor,
                  "Share of the input's surface the decoded map must carry within 1 % of the diagonal; below it a warning, "
                  "or a refusal with --strict")
      ->capture_default_str()
      ->check(number_in(0.0, 1.0));
}

void add_encode_quality_options(CLI::App* app, EncodeQuality& q, const std::string& strict_help) {
  add_min_part_option(app, q.min_part);
  add_repair_options(app);
  add_fill_holes_option(app, q.fill_holes);
  add_max_memory_option(app, q.max_memory);
  app->add_flag("--strict", q.strict, strict_help);
  add_min_carried_option(app, q.min_carried);
  add_face_error_option(app, q.face_error);
}

}  // namespace sdm::cli
