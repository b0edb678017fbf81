#pragma once
/// Curve-skeleton extraction (paper 3.1, Au et al. 2008): Laplacian contraction, connectivity
/// surgery of the contracted mesh into a 1-D graph, and refinement (nodes moved to the centre of
/// the original vertices they own, short edges and short end branches merged). Like CGAL's
/// skeletonization (contract, collapse, convert), each stage can be called alone:
///   contract_mesh.h      Laplacian contraction
///   medial_poles.h       the medial poles (the second candidate's contracted shape)
///   surgery.h            connectivity surgery: contracted mesh -> graph + vertex clusters
///   refine_skeleton.h    refinement: merges, placement inside, crossing edges bent
///   choose_candidate.h   contraction vs medial candidate (genus, edges outside, tube error)
///   contraction_proxy.h  the remeshed proxy of large parts and the map back to their vertices
/// This function only orchestrates them, part by part.
#include "libstm/core/progress.h"
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/skeleton.h"
#include "libstm/skeleton/skeleton_options.h"

namespace sdm {

/// Extracts the curve skeleton of a closed triangle mesh, each connected part separately (one
/// graph component per part). Two candidates per part go through surgery and refinement: the
/// Laplacian contraction and the medial poles (medial_poles.h); the one with the part's genus as
/// cycles, no edge outside and the smaller tube error (distance to the skeleton against the medial
/// radius) is kept. Every vertex maps to exactly one node, every node owns at least one
/// vertex; a part of genus g gives a component with g independent cycles. Nodes are kept inside
/// the volume. Deterministic.
Skeleton extract_skeleton(const Mesh& mesh, const SkeletonOptions& options = {}, const Progress& progress = nullptr,
                          SkeletonStats* stats = nullptr);

}  // namespace sdm
