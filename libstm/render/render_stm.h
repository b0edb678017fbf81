#pragma once
/// Rendering a mesh with its skeleton texture map and no stored uv (paper 4, DESIGN 4.7): the
/// mesh's positions, the skeleton node of each vertex (layout.skeleton.vertex_node) and the layout
/// go to the GPU; a geometry shader chooses each triangle's segment with the rule of assign_faces,
/// the fragment shader maps the interpolated position with the capsule mapping (a GLSL copy of
/// capsule_uv) and samples the atlas trilinearly, with derivatives of the angle unwrapped against a
/// per-triangle reference so the seam at phi = 0 shows no line. Any uv the mesh has is ignored.
#include "libstm/render/gl_context.h"
#include "libstm/core/image.h"
#include "libstm/layout/layout.h"
#include "libstm/mesh/mesh.h"
#include "libstm/render/render_mesh.h"

#include <cstdint>
#include <vector>

namespace sdm {

/// What the shaders computed, per pixel of a single-sample pass from the same camera (for checks
/// against the CPU mapping; 0 where nothing is drawn):
///   coordinates: (atlas x, atlas y in texels, segment, face index); alpha of `positions` marks coverage
///   positions:   (x, y, z in model coordinates, 1)
struct StmRenderProbe {
  FloatImage coordinates, positions;
};

/// Draws `mesh` textured with `atlas` (a render_atlas result for `layout`) like render_mesh draws
/// it with its own uv: same camera, options and compositing (options.texture is ignored; normals
/// are area-weighted vertex normals, or face normals with flat_shading). `mask` as in render_mesh.
/// \throw InputError when the layout's skeleton does not belong to the mesh (vertex counts differ)
/// or the atlas is not layout.size^2.
Image render_stm(GlContext& gl, const Mesh& mesh, const Layout& layout, const Image& atlas, const RenderOptions& options,
                 std::vector<uint8_t>* mask = nullptr, StmRenderProbe* probe = nullptr);

}  // namespace sdm
