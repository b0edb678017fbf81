// CGAL's Poisson surface reconstruction (Kazhdan et al. 2006) of a point cloud without normals, as
// CGAL's own reconstruction tutorial runs it: jet-fitted normals (24 neighbours), oriented by a
// minimum spanning tree (mst_orient_normals, 24 neighbours; points it cannot orient are dropped),
// then poisson_surface_reconstruction_delaunay with the average spacing of 6 neighbours and its
// default parameters. Reads .xyz (x y z per line), writes the surface as OFF and prints the time of
// the whole process. The point-cloud benchmark judges it beside sdm's decode
// (scripts/bench_cloud_maps.sh with CGAL_POISSON).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Point_set_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/compute_average_spacing.h>
#include <CGAL/jet_estimate_normals.h>
#include <CGAL/mst_orient_normals.h>
#include <CGAL/poisson_surface_reconstruction.h>

#include <chrono>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Vector = Kernel::Vector_3;
using Point_set = CGAL::Point_set_3<Point, Vector>;
using Surface = CGAL::Surface_mesh<Point>;

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: cgal_poisson CLOUD.xyz OUT.off\n";
    return 2;
  }
  const auto t0 = std::chrono::steady_clock::now();
  Point_set points;
  points.add_normal_map();
  std::ifstream in(argv[1]);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    double x, y, z;
    if (words >> x >> y >> z) points.insert(Point(x, y, z));
  }
  if (points.size() < 10) {
    std::cerr << argv[1] << ": fewer than 10 points\n";
    return 2;
  }
  CGAL::jet_estimate_normals<CGAL::Sequential_tag>(points, 24);
  const auto unoriented = CGAL::mst_orient_normals(points, 24);
  const std::size_t dropped = static_cast<std::size_t>(std::distance(unoriented, points.end()));
  points.remove(unoriented, points.end());
  points.collect_garbage();
  const double spacing = CGAL::compute_average_spacing<CGAL::Sequential_tag>(points, 6);
  Surface surface;
  const bool ok = CGAL::poisson_surface_reconstruction_delaunay(points.begin(), points.end(), points.point_map(),
                                                                points.normal_map(), surface, spacing);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!ok || surface.is_empty()) {
    std::cerr << argv[1] << ": Poisson reconstruction failed\n";
    return 1;
  }
  std::ofstream out(argv[2]);
  out << surface;
  std::cout << points.size() << " points (" << dropped << " not oriented, dropped), " << surface.number_of_vertices()
            << " vertices, " << surface.number_of_faces() << " faces, " << seconds << " s\n";
  return out ? 0 : 1;
}
