// CGAL's mean-curvature-flow skeletonization (Tagliasacchi et al. 2012) with its default
// parameters, as a user would run it: read a closed triangle mesh, extract the skeleton, write
// its nodes and edges (OBJ: v and l lines). The benchmark times this whole process against
// `sdm skeleton MESH -o S.json` (scripts/bench_cgal_skeleton.sh).
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mean_curvature_flow_skeletonization.h>
#include <CGAL/extract_mean_curvature_flow_skeleton.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/boost/graph/IO/polygon_mesh_io.h>

#include <boost/graph/adjacency_list.hpp>
#include <fstream>
#include <iostream>

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Triangle_mesh = CGAL::Surface_mesh<Point>;
using Skeletonization = CGAL::Mean_curvature_flow_skeletonization<Triangle_mesh>;
using Skeleton = Skeletonization::Skeleton;

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: cgal_skeleton MESH OUT.obj\n";
    return 2;
  }
  Triangle_mesh mesh;
  // Polygons are triangulated first (the double torus is made of quads), as the skeletonizer needs.
  if (CGAL::IO::read_polygon_mesh(argv[1], mesh) && !CGAL::is_triangle_mesh(mesh)) CGAL::Polygon_mesh_processing::triangulate_faces(mesh);
  if (mesh.is_empty() || !CGAL::is_triangle_mesh(mesh) || !CGAL::is_closed(mesh)) {
    std::cerr << argv[1] << ": not a closed triangle mesh\n";
    return 2;
  }
  Skeleton skeleton;
  CGAL::extract_mean_curvature_flow_skeleton(mesh, skeleton);
  std::ofstream out(argv[2]);
  for (auto v : CGAL::make_range(vertices(skeleton))) out << "v " << skeleton[v].point << "\n";
  for (auto e : CGAL::make_range(edges(skeleton)))
    out << "l " << source(e, skeleton) + 1 << " " << target(e, skeleton) + 1 << "\n";
  std::cerr << num_vertices(skeleton) << " nodes, " << num_edges(skeleton) << " edges\n";
  return out ? 0 : 1;
}
