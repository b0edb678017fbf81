#pragma once
/// Pictures of a skeleton inside its mesh: the skeleton as tubes and node balls, composited over a
/// faded (semi-transparent looking) render of the surface, so the whole skeleton stays visible.
#include "libstm/render/render_mesh.h"
#include "libstm/skeleton/skeleton.h"

namespace sdm {

/// Tubes along the skeleton's edges and balls at its nodes (radius: `radius` and 2 * radius), as
/// one triangle mesh for the renderer. Balls at branch and end nodes are larger, so the structure
/// reads at a glance.
Mesh skeleton_tubes(const Skeleton& skeleton, double radius);

/// Renders `mesh` with `options`, then the skeleton with the same camera (framed on the mesh), and
/// blends: surface at `surface_opacity` over white, skeleton drawn on top.
Image render_with_skeleton(GlContext& gl, const Mesh& mesh, const Skeleton& skeleton, RenderOptions options,
                           double surface_opacity = 0.45);

}  // namespace sdm
