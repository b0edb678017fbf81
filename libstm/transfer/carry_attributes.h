#pragma once
/// Per-vertex attributes carried from a source onto a target through a point correspondence (the
/// TextureTransfer's: per target vertex a source face and barycentric coordinates in it), e.g.
/// `sdm transfer --vertex-colors`: the source's vertex colours, or its texture, on the target's
/// vertices.
#include "libstm/core/image.h"
#include "libstm/mesh/mesh.h"
#include "libstm/registration/carry_skeleton.h"
#include "libstm/render/gl_context.h"
#include "libstm/skeleton/skeleton.h"

#include <Eigen/Dense>
#include <vector>

namespace sdm {

/// Per target vertex (one per correspondence entry, in order): the barycentric blend of the source
/// colours (`source_colors`, one per source vertex) at the three corners of its source face, in the
/// face's corner order (fv_range, as SourcePoint's weights). A colour that varies linearly over
/// the surface is thus reproduced exactly at the source point.
/// \throw InputError when the colour count differs from the source's vertex count or a face index
/// lies outside the source.
std::vector<Eigen::Vector3f> carry_vertex_colors(const Mesh& source, const std::vector<Eigen::Vector3f>& source_colors,
                                                 const std::vector<SourcePoint>& correspondence);

/// Per target vertex: the source's texture sampled (bilinearly, repeating, as the renderer does) at
/// the uv of its source point, the barycentric blend of its face's corner uv: inside one face the uv
/// are linear, so this is the colour the renderer shows there. Blending the colours sampled at the
/// three corners instead goes wrong on the STM's seam faces, whose corner uv are unwrapped past
/// their rectangle into texels of the margin and beyond (measured on the ypsilon onto its remesh:
/// 26 of 1981 vertices off by 8/255 to 138/255, mean 1.3/255; sampled at the point, 1 vertex at a
/// capsule pole, mean 0.5/255). \throw InputError when the source has no uv, the texture is empty
/// or a face index lies outside the source.
std::vector<Eigen::Vector3f> carry_texture_colors(const Mesh& source, const Image& texture,
                                                  const std::vector<SourcePoint>& correspondence);

/// A mesh with uv and the texture they address.
struct TexturedMesh {
  Mesh mesh;
  Image texture;
};

/// The other way round, for a source with vertex colours and no texture: `mesh` with its own STM
/// uv (layout around `skeleton`, a size x size atlas with `margin` texels) and the atlas in which
/// its colours (`colors`, one per vertex, interpolated over each face) are painted, so that it can be
/// the source of a texture transfer. The vertices stay as they are (same order).
/// \throw InputError when the colour count differs from the vertex count or the skeleton does not
/// belong to the mesh.
TexturedMesh texture_from_vertex_colors(GlContext& gl, const Mesh& mesh, const std::vector<Eigen::Vector3f>& colors,
                                        const Skeleton& skeleton, int size, int margin);

/// The texture's RGB in [0, 1] at uv (0, 0 the image's bottom-left corner, as in OBJ), bilinear
/// between texel centres, repeating outside [0, 1]. `texture` must not be empty.
Eigen::Vector3f sample_texture(const Image& texture, const Eigen::Vector2d& uv);

}  // namespace sdm
