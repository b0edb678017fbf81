#pragma once
/// Offscreen rendering of a mesh to an image, headless through GlContext: the picture a user looks
/// at, and the measurement tool for texture quality (PSNR between two renders from one camera).
#include "libstm/render/gl_context.h"
#include "libstm/core/image.h"
#include "libstm/mesh/mesh.h"

#include <Eigen/Dense>
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

namespace sdm {

/// A camera in world (mesh) coordinates: view maps world to eye space (camera looks down -z),
/// projection maps eye space to clip space (OpenGL conventions, column vectors).
struct Camera {
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  Eigen::Matrix4d projection = Eigen::Matrix4d::Identity();
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();     ///< camera position (perspective)
  Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< point looked at: the box centre
  bool orthographic = false;
};

/// Frames the box [lo, hi] for a width x height image. The camera looks at the box centre from
/// direction frame * (cos(el) sin(az), sin(el), cos(el) cos(az)): frame's y column is up, azimuth 0
/// / elevation 0 looks along minus its z column, positive azimuth moves the camera towards its x
/// column. `frame` is a rotation (columns orthonormal, determinant 1); the identity gives the world's
/// axes: +y up, looking along -z. The box's bounding sphere (radius half
/// the diagonal) exactly fits the smaller image dimension: perspective with a 30 degree field of
/// view on that dimension, or orthographic. The framing depends only on the box, the angles and
/// the image size, so two meshes with the same box get the same camera.
/// \throw InputError when the box is empty or degenerate to a point.
Camera frame_camera(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double azimuth_deg, double elevation_deg,
                    int width, int height, bool orthographic = false, const Eigen::Matrix3d& frame = Eigen::Matrix3d::Identity());

/// The axes a model is best seen along (a frame for RenderOptions::frame), from the principal axes
/// of its surface (the second moments of its area, exact per triangle). A model lying down, whose
/// file's +y is within 45 degrees of its shortest axis (a person lying along z, y through the
/// chest), is stood up: its longest axis is up (y, vertical on screen). Any other keeps the file's
/// +y up: a person standing along y, but also a quadruped whose longest axis runs diagonally from
/// muzzle to rump and would stand it on its head. Looked along (z, at azimuth and elevation 0): the
/// shortest axis, made square to up, so a person is seen from the front or back and a quadruped
/// from its side. Signs: up and z point the way of the world axis each is closest to; x = y cross z.
/// `up`, when given (a unit vector: the file's up, known), is up instead of the guess.
Eigen::Matrix3d principal_view_frame(const Mesh& mesh, const std::optional<Eigen::Vector3d>& up = std::nullopt);

/// The frame that shows a model whose up direction is `up` (any non-zero vector) upright: the
/// smallest rotation taking +y onto up (for -y a half turn about z). A +z-up model (Blender's, most
/// CAD and STL files) is then looked at from -y, its front in Blender; +y gives the identity.
Eigen::Matrix3d up_view_frame(const Eigen::Vector3d& up);

struct RenderOptions {
  int width = 800, height = 800;
  double azimuth_deg = 30, elevation_deg = 20;
  /// The axes the angles refer to (frame_camera): the identity keeps the world's, +y up.
  Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();
  bool orthographic = false;  ///< default: perspective, 30 degree field of view
  /// Unlit draws the surface colour as it is (texture colour, or `color`): two tessellations of one
  /// textured shape then give the same pixels, so PSNR measures only the texture mapping.
  /// Lit: headlight Lambert (two-sided) plus `ambient`.
  bool unlit = false;
  double ambient = 0.25;
  /// Normals: area-weighted average of the faces around a vertex that bend less than
  /// crease_angle_deg from the corner's face (sharp edges stay sharp); flat_shading uses face normals.
  double crease_angle_deg = 60;
  bool flat_shading = false;
  /// When set, the mesh must have per-halfedge uv (mesh.has_halfedge_texcoords2D()); uv (0,0) is the
  /// image's bottom-left corner, as in OBJ. Sampled bilinearly with mipmaps, repeating.
  const Image* texture = nullptr;
  Eigen::Vector3f color = Eigen::Vector3f(0.78f, 0.78f, 0.80f);  ///< surface colour without texture, RGB in [0,1]
  /// When set and no texture is: a colour per mesh vertex (RGB in [0, 1], one per vertex), blended
  /// across each face, in place of `color`.
  const std::vector<Eigen::Vector3f>* vertex_colors = nullptr;
  std::array<uint8_t, 4> background = {255, 255, 255, 255};
  /// Framing box; when bbox_min > bbox_max in any coordinate (the default), the mesh's own box.
  Eigen::Vector3d bbox_min = Eigen::Vector3d::Constant(1.0), bbox_max = Eigen::Vector3d::Constant(-1.0);
  int samples = 4;  ///< multisampling (1 = off); edges only, interiors are identical either way
  /// Drawn after the mesh, with the context current, the target bound and depth testing on: for
  /// overlays (skeleton lines...) that share the mesh's camera and depth buffer.
  std::function<void(const Camera&)> overlay;
};

/// Renders `mesh` with `options` in the context `gl` (made current here). The result is an opaque
/// RGBA image (object composited over the background); `mask`, when given, receives width*height
/// bytes, 255 where the object covers at least half of the pixel, 0 elsewhere (for psnr()).
/// \throw InputError for an empty mesh, a texture without uv, or an invalid image size.
Image render_mesh(GlContext& gl, const Mesh& mesh, const RenderOptions& options, std::vector<uint8_t>* mask = nullptr);

/// Renders are read back premultiplied over transparent black (alpha = coverage): this puts them
/// over `background` and, when `mask` is given, marks the pixels at least half covered (255).
void composite_over_background(Image& img, const std::array<uint8_t, 4>& background, std::vector<uint8_t>* mask);

}  // namespace sdm
