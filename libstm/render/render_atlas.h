#pragma once
/// Rendering into the STM atlas (paper 3.4, 3.5, 4; DESIGN 4.6) with GL through EGL: every
/// segment's triangles are drawn into its rectangle at their capsule coordinates, interpolating a
/// per-corner attribute (the source uv, to remap a texture; float values, for displacement).
///  - Seam: triangles are drawn at u, u - h and u + h, so both sides of phi = 0 are filled and
///    the margin around the axis continues the rectangle periodically.
///  - Along the axis: the faces of the segments sharing a node with this one (and any face with a
///    corner at one of its nodes) are drawn too, with this segment's mapping, behind its own faces:
///    the real surface next to the segment fills the cap area and the rectangle's surroundings, and
///    a fragment whose triangle a renderer assigns to a neighbouring segment (a tie in
///    assign_faces decided the other way in float) still finds its texture.
///  - Texels no triangle covers (margins past the poles, unused atlas area) are filled by
///    push-pull from their covered neighbours, so bilinear filtering and mip-mapping never pull
///    in black.
#include "libstm/core/progress.h"
#include "libstm/render/gl_context.h"
#include "libstm/core/image.h"
#include "libstm/layout/layout.h"
#include "libstm/mesh/mesh.h"

#include <Eigen/Dense>
#include <functional>
#include <string>
#include <vector>

namespace sdm {

struct AtlasOptions {
  bool fill = true;  ///< push-pull fill of uncovered texels (off: they stay transparent black)
  Progress progress;
};

/// Remaps `source_texture` (sampled trilinearly at the mesh's per-halfedge uv, uv (0,0) = the
/// image's bottom-left corner, repeating) into a layout.size^2 RGBA atlas (rows top to bottom as a
/// PNG, atlas y = 0 at the bottom; alpha 255). `covered`, when given, receives size^2 bytes, 255
/// where a triangle covered the texel before filling. Faces are assigned with assign_faces.
/// \throw InputError when the mesh has no uv, the layout does not belong to the mesh, or the
/// atlas is larger than the GL limit.
Image render_atlas(GlContext& gl, const Mesh& mesh, const Layout& layout, const Image& source_texture,
                   const AtlasOptions& options = {}, std::vector<uint8_t>* covered = nullptr);

/// The same for float attributes: corner_values[3 f + k] is the value at the k-th corner of face f
/// (mesh.fv_range order). Returns a size^2 x 4 float atlas (rows top to bottom); `covered` as above.
FloatImage render_atlas_values(GlContext& gl, const Mesh& mesh, const Layout& layout,
                               const std::vector<Eigen::Vector4f>& corner_values, const AtlasOptions& options = {},
                               std::vector<uint8_t>* covered = nullptr);

/// Push-pull fill (Gortler et al. 1996): every texel with weight 0 gets the value of the coarser
/// levels of a pyramid of weighted averages, so holes take a smooth blend of their surroundings.
/// `values` is width * height * channels, `weight` width * height (0 = empty, > 0 = keep).
void push_pull_fill(std::vector<float>& values, const std::vector<float>& weight, int width, int height, int channels);

}  // namespace sdm
