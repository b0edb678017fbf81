#include "apps/view_up.h"

#include "libstm/core/errors.h"
#include "libstm/mesh/check_mesh_file.h"

namespace sdm::cli {

void add_up_option(CLI::App* app, std::string& value, const std::string& flag, const std::string& whose) {
  app->add_option(flag, value,
                  "Up axis of " + whose + " in its file: x, y, z, -x, -y or -z (z for Blender's, most CAD and STL files); "
                  "auto: the file's own where its format states one (glTF: +y), else +y");
}

ViewUp view_up(const std::string& value, const std::string& mesh_path, const std::string& flag) {
  ViewUp up;
  if (value.empty() || value == "auto") {
    const std::string ext = sdm::lower_extension(mesh_path);
    if (ext == ".glb" || ext == ".gltf") up.from = "glTF specification";
    return up;
  }
  std::string v = value;
  double sign = 1;
  if (v.size() == 2 && (v[0] == '+' || v[0] == '-')) {
    sign = v[0] == '-' ? -1 : 1;
    v = v.substr(1);
  }
  if (v.size() != 1 || (v[0] != 'x' && v[0] != 'y' && v[0] != 'z'))
    throw sdm::InputError(flag + " '" + value + "' is not an axis: give x, y, z, -x, -y, -z (a sign + or - allowed) or auto");
  up.axis = sign * Eigen::Vector3d::Unit(v[0] - 'x');
  up.name = std::string(sign < 0 ? "-" : "+") + v;
  up.from = flag;
  return up;
}

}  // namespace sdm::cli
