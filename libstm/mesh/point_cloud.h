#pragma once
/// Scans without faces (DECISIONS 1, "Point clouds"): positions with optional normals and colours,
/// read from .xyz, PCL's .pcd, and PLY or OFF files with vertices and no faces; checked like a mesh
/// (coordinates finite and within range, counts within the file, duplicates merged and counted)
/// and refused when no skeleton can come from them (too few points, all on a plane or a line).
#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace sdm {

struct PointCloud {
  std::vector<Eigen::Vector3d> points;
  std::vector<Eigen::Vector3d> normals;  ///< one unit vector per point, or empty
  std::vector<Eigen::Vector3f> colors;   ///< per point, RGB in [0, 1], or empty
  long no_returns = 0;  ///< PCD points with x, y and z all NaN (PCL's mark of a missing return), dropped on read
};

/// Fewest points a skeleton is extracted from (after duplicates are merged).
constexpr int kMinCloudPoints = 200;

/// What reading and preparing a cloud found.
struct CloudReport {
  long points_read = 0;        ///< as in the file (PCD's missing returns not counted)
  long no_returns = 0;         ///< PCD points all NaN, dropped
  long duplicates = 0;         ///< points at the position of an earlier one, merged into it
  long points = 0;             ///< after merging
  double mean_spacing = 0;     ///< mean distance from a point to its nearest other point
  bool normals_in_file = false;
  bool normals_estimated = false;
  bool colors = false;
  Eigen::Vector3d bbox_min = Eigen::Vector3d::Zero(), bbox_max = Eigen::Vector3d::Zero();
  /// Principal extents (square roots of the covariance's eigenvalues), largest first.
  Eigen::Vector3d extents = Eigen::Vector3d::Zero();
  nlohmann::json to_json() const;
};

/// Whether `path` holds a point cloud rather than a mesh: .xyz and .pcd always; .ply and .off when
/// their header counts no faces. Reads the header only; false for anything unreadable (the mesh
/// reader then says why).
bool is_point_cloud_file(const std::string& path);

/// Reads a point cloud: .xyz (`x y z` or `x y z nx ny nz` per line, `#` comments), PLY (ASCII or
/// binary; x, y, z with nx, ny, nz and red, green, blue when present; a face element must be
/// empty), OFF with zero faces, PCD (ascii or binary; binary_compressed refused).
/// \throw InputError
/// naming the file, the line or point and the fix for a missing, empty or malformed file, a count
/// the file does not hold, and a NaN, infinite or out-of-range coordinate. Nothing is allocated
/// beyond what the file's size can hold.
PointCloud read_point_cloud(const std::string& path);

/// Merges duplicates (the first of each position kept; a normal kept from it), measures the cloud,
/// and throws InputError naming `what` when no skeleton can come from it: fewer than
/// kMinCloudPoints distinct points, all on a line or a plane (principal extents), coordinates not
/// finite. `index_of`, when given, receives per point as read the index it has after merging.
CloudReport prepare_cloud(PointCloud& cloud, const std::string& what, std::vector<int>* index_of = nullptr);

/// Reads and prepares (read_point_cloud, prepare_cloud); with `normals`, estimates them when the
/// file has none or has zero vectors among them (estimate_normals).
PointCloud load_point_cloud(const std::string& path, CloudReport* report = nullptr, bool normals = true);

/// Unit normals from the principal axes of each point's `k` nearest neighbours, oriented
/// consistently by propagation along a minimum spanning tree of the neighbourhood graph weighted
/// 1 - |n_i . n_j| (Hoppe et al. 1992), each connected part turned so that its normals point away
/// from its centroid on the whole.
std::vector<Eigen::Vector3d> estimate_normals(const std::vector<Eigen::Vector3d>& points, int k = 12);

}  // namespace sdm
