#pragma once
/// Triangulating one polygon of an input file. A fan from the first corner gives a
/// 1000-gon cap one vertex of valence 1000 and 998 needles: the base mesh's decimation checks every
/// collapse around that vertex against all its faces (quadratic in the polygon's size), and a fan
/// of a non-convex polygon folds triangles over each other.
///
/// Ear clipping (Meisters 1975, "Polygons have ears"; the greedy shortest-diagonal rule that
/// approximates the minimum-weight triangulation): the polygon is projected onto the plane of its
/// Newell normal and the ear whose cut is shortest goes first. On a regular n-gon that removes
/// every other corner in turn, so no corner gets more than about 2 log2 n edges (10000-gon: 25;
/// cutting the best-shaped ear first instead grew a fan again, valence 5080), and no cut crosses a
/// reflex corner.
#include <Eigen/Dense>

#include <array>
#include <vector>

namespace sdm {

/// corners: the polygon's corners in order (3 or more). Returns corners.size() - 2 triangles as
/// indices into `corners`, oriented like the polygon. A quadrilateral keeps the diagonal from corner 0
/// (as a fan, so quad meshes triangulate as before) unless that diagonal lies outside it. Degenerate
/// polygons (collinear or repeated corners) still get n - 2 triangles: what cannot be cut as an ear
/// is cut as a fan of the corners left.
std::vector<std::array<int, 3>> triangulate_polygon(const std::vector<Eigen::Vector3d>& corners);

}  // namespace sdm
