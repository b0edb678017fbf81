#pragma once
/// A mesh's vertices and faces renumbered in a spatially coherent order: vertices along a Morton
/// (Z-order) curve through the bounding box, faces by their corners' new numbers. Neighbours then
/// sit near each other in memory, and every pass that follows edges (validation, the halfedge
/// build, contraction, closest points) reads far fewer cache lines. An isotropic remesh ends with
/// OpenMesh's garbage collection, which fills the holes of collapsed elements from the end of its
/// arrays and scatters the numbering, so that a face's corners lie far apart in memory
/// (docs/BENCHMARKS.md, "Loading large meshes").
#include "libstm/mesh/mesh.h"

namespace sdm {

/// The same surface (points, faces with their corner order and orientation, per-corner uv when the
/// mesh has them), renumbered: vertex i of the result is the i-th along the Morton curve (ties
/// keep their order), faces sorted by their smallest, middle and largest new corner numbers.
Mesh spatially_ordered(const Mesh& mesh);

/// The same on a soup (points, their colours, triangles, per-corner uv), before any mesh is built.
MeshSoup spatially_ordered(const MeshSoup& soup);

/// Whether the mesh's numbering is scattered: over (up to) 10,000 faces spread through the list,
/// the median distance between a face's smallest and largest corner numbers exceeds 5 % of the
/// vertices (a random numbering gives about 40 %, a coherent one under 1 %).
bool scattered_numbering(const Mesh& mesh);
bool scattered_numbering(const std::vector<std::array<int, 3>>& triangles, size_t vertices);

/// Above this many vertices, the stages that remesh a copy of their input (the skeleton's
/// contraction proxy, the encoder's base source) renumber the copy first when scattered_numbering
/// holds (docs/BENCHMARKS.md, "Loading large meshes"). Below it the copy keeps the input's
/// numbering, so results on smaller meshes do not change.
constexpr int kRenumberCopiesFrom = 100000;

}  // namespace sdm
