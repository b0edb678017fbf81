#pragma once
// Point clouds on the command line (libstm/mesh/point_cloud.h): `sdm skeleton` and `sdm info` of
// a scan without faces. The mesh commands hand a cloud over here when is_point_cloud_file says so.
#include <string>

namespace sdm::cli {

/// `sdm skeleton CLOUD -o OUT [--obj OBJ] [--json]`: the point-cloud skeleton (point_skeleton.h),
/// written as the mesh path writes its skeleton (vertex_node per distinct point, in file order).
int cloud_skeleton(const std::string& path, const std::string& out, const std::string& obj, bool json);

/// `sdm stm CLOUD -o LAYOUT [--uv-obj OBJ] [--json]`: the layout of the cloud's surface around its
/// skeleton (cloud_layout.h); --uv-obj writes that surface with its STM coordinates.
int cloud_stm(const std::string& path, const std::string& out, int size, int margin, const std::string& uv_obj, bool json);

/// `sdm info CLOUD [--json]`: points read, duplicates merged, mean spacing, normals, bounding box.
int cloud_info(const std::string& path, bool json);

}  // namespace sdm::cli
