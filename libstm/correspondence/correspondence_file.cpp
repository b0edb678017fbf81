#include "libstm/correspondence/correspondence_file.h"

#include <nlohmann/json.hpp>
#include <sstream>

namespace sdm {

std::string correspondence_text(const std::vector<SourcePoint>& c, bool json) {
  std::ostringstream o;
  o.precision(9);
  if (json) {
    nlohmann::json faces = nlohmann::json::array(), bary = nlohmann::json::array();
    for (const auto& p : c) faces.push_back(p.face), bary.push_back({p.barycentric[0], p.barycentric[1], p.barycentric[2]});
    o << nlohmann::json({{"target_vertices", c.size()}, {"source_face", faces}, {"barycentric", bary}}).dump() << "\n";
    return o.str();
  }
  o << "# sdm correspondence: one line per target vertex, in order: source face, then the\n"
       "# barycentric coordinates of the source point on it (weights of the face's corners 0, 1, 2)\n";
  for (const auto& p : c) o << p.face << " " << p.barycentric[0] << " " << p.barycentric[1] << " " << p.barycentric[2] << "\n";
  return o.str();
}

}  // namespace sdm
