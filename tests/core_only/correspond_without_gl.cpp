// A program that links only sdm::core (no EGL, no GL, no OpenEXR, no OpenSubdiv) and builds a dense
// correspondence: the correspondence stands on its own, without the renderer that transfer uses.
// Built and run by the tests (tests/CMakeLists.txt).
//
// The paper's ypsilon onto another tessellation of itself, turned a quarter turn and moved: every
// target vertex must be shown the source point at its own place (the motion undone), within a
// small share of the diagonal, and the target recognised as the source's shape.
#include "libstm/correspondence/correspond.h"
#include "libstm/mesh/primitives.h"
#include "libstm/skeleton/extract_skeleton.h"

#include <algorithm>
#include <iostream>

int main() {
  const sdm::Mesh source = sdm::make_primitive("ypsilon");
  sdm::Mesh target = sdm::make_primitive("ypsilon", 2 * int(source.n_vertices()));
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  const Eigen::Vector3d shift(3, -1, 2);
  for (auto v : target.vertices()) {
    const Eigen::Vector3d p = turn * sdm::point(target, v) + shift;
    target.set_point(v, sdm::Mesh::Point(p.x(), p.y(), p.z()));
  }
  const sdm::Correspondence c =
      sdm::correspond(source, sdm::extract_skeleton(source), target, sdm::extract_skeleton(target));
  Eigen::Vector3d lo, hi;
  sdm::bounding_box(source, lo, hi);
  const double diagonal = (hi - lo).norm();
  double worst = 0, mean = 0;
  for (auto v : target.vertices()) {
    const sdm::SourcePoint& s = c.points[size_t(v.idx())];
    Eigen::Vector3d shown = Eigen::Vector3d::Zero();
    int k = 0;
    for (auto u : source.fv_range(source.face_handle(s.face))) shown += s.barycentric[k++] * sdm::point(source, u);
    const double d = (turn.transpose() * (sdm::point(target, v) - shift) - shown).norm() / diagonal;
    worst = std::max(worst, d), mean += d / double(target.n_vertices());
  }
  const bool ok = c.kind == sdm::CorrespondenceKind::carried && c.points.size() == target.n_vertices() && mean < 0.002 && worst < 0.01;
  std::cout << "ypsilon onto its turned remesh from sdm::core alone: " << sdm::kind_name(c.kind) << ", source points off by "
            << 100 * mean << " % of the diagonal on average, " << 100 * worst << " % at worst: " << (ok ? "ok" : "WRONG") << std::endl;
  return ok ? 0 : 1;
}
