// A program that links only sdm::core (no EGL, no GL, no OpenEXR, no OpenSubdiv) and extracts a
// skeleton: the core layer must stand on its own. Built and run by the tests (tests/CMakeLists.txt).
//
// The paper's ypsilon has three arms meeting at one junction and genus 0, so its skeleton must be a
// tree with three ends and one branch node, and every vertex must map to a node.
#include "libstm/mesh/primitives.h"
#include "libstm/skeleton/extract_skeleton.h"

#include <iostream>

int main() {
  const sdm::Mesh mesh = sdm::make_primitive("ypsilon");
  const sdm::Skeleton s = sdm::extract_skeleton(mesh);
  const bool ok = s.end_nodes() == 3 && s.branch_nodes() == 1 && s.cycles() == 0 && s.components() == 1 &&
                  s.vertex_node.size() == mesh.n_vertices();
  std::cout << "ypsilon skeleton from sdm::core alone: " << s.nodes.size() << " nodes, " << s.end_nodes() << " ends, "
            << s.branch_nodes() << " junctions, " << s.cycles() << " cycles: " << (ok ? "ok" : "WRONG") << std::endl;
  return ok ? 0 : 1;
}
