#pragma once
// A mesh's vertices and faces renumbered in a spatially coherent order: vertices along a Morton
// (Z-order) curve through the bounding box, faces by their corners' new numbers. Neighbours then
// sit near each other in memory, and every pass that follows edges (validation, the halfedge
// build, contraction, closest points) reads far fewer cache lines. An isotropic remesh ends with
// OpenMesh's garbage collection, which fills the holes of collapsed elements from the end of its
// arrays and scatters the numbering: a 449k-vertex remesh of bunny00 as `sdm remesh` wrote it had
// its faces' corners a median 108k indices apart, and loading it took 0.72 s; the same mesh in this
// order 0.41 s (docs/BENCHMARKS.md, "Loading large meshes").
#include "libstm/mesh/mesh.h"

namespace sdm {

/// The same surface (points, faces with their corner order and orientation, per-corner uv when the
/// mesh has them), renumbered: vertex i of the result is the i-th along the Morton curve (ties
/// keep their order), faces sorted by their smallest, middle and largest new corner numbers.
Mesh spatially_ordered(const Mesh& mesh);

}  // namespace sdm
