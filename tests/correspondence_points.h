#pragma once
// What the tests of `sdm correspond` and `sdm transfer --correspondence` read back: the source
// point of each line of a correspondence file (.txt: face and three barycentric weights a line).
#include "libstm/mesh/mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/registration/carry_skeleton.h"

#include <Eigen/Core>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace test_util {

/// Per line of the correspondence file at `path` (comments '#' and empty lines skipped), the
/// position of its source point on `source`.
inline std::vector<Eigen::Vector3d> read_points(const std::string& path, const sdm::Mesh& source) {
  std::ifstream in(path);
  std::vector<Eigen::Vector3d> out;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    sdm::SourcePoint p;
    s >> p.face >> p.barycentric[0] >> p.barycentric[1] >> p.barycentric[2];
    out.push_back(sdm::position_of(source, p));
  }
  return out;
}

}  // namespace test_util
