#include "libstm/transfer/carry_attributes.h"

#include "libstm/core/errors.h"
#include "libstm/layout/compute_layout.h"
#include "libstm/layout/stm_coordinates.h"
#include "libstm/render/render_atlas.h"

#include <algorithm>

#include <array>
#include <cmath>
#include <string>

namespace sdm {

namespace {

// The source face of correspondence entry j, checked against the source.
Mesh::FaceHandle source_face(const Mesh& source, const std::vector<SourcePoint>& correspondence, size_t j) {
  const int f = correspondence[j].face;
  if (f < 0 || size_t(f) >= source.n_faces())
    throw InputError("correspondence entry " + std::to_string(j) + " names source face " + std::to_string(f) + ", but the source has " +
                     std::to_string(source.n_faces()) + " faces: the correspondence was made for another source");
  return source.face_handle(f);
}

// Texel (x, y) of the texture, wrapped, as RGB in [0, 1] (a grey image gives grey).
Eigen::Vector3f texel(const Image& t, int x, int y) {
  x = ((x % t.width) + t.width) % t.width;
  y = ((y % t.height) + t.height) % t.height;
  const uint8_t* p = t.at(x, y);
  const int g = t.channels >= 3 ? 1 : 0, b = t.channels >= 3 ? 2 : 0;
  return Eigen::Vector3f(p[0], p[g], p[b]) / 255.f;
}

}  // namespace

std::vector<Eigen::Vector3f> carry_vertex_colors(const Mesh& source, const std::vector<Eigen::Vector3f>& source_colors,
                                                 const std::vector<SourcePoint>& correspondence) {
  if (source_colors.size() != source.n_vertices())
    throw InputError(std::to_string(source_colors.size()) + " source colours for a source with " + std::to_string(source.n_vertices()) +
                     " vertices: give one colour per source vertex");
  std::vector<Eigen::Vector3f> out;
  out.reserve(correspondence.size());
  for (size_t j = 0; j < correspondence.size(); ++j) {
    const Eigen::Vector3d& w = correspondence[j].barycentric;
    Eigen::Vector3f c = Eigen::Vector3f::Zero();
    int k = 0;
    for (auto v : source.fv_range(source_face(source, correspondence, j))) c += float(w[k++]) * source_colors[v.idx()];
    out.push_back(c);
  }
  return out;
}

TexturedMesh texture_from_vertex_colors(GlContext& gl, const Mesh& mesh, const std::vector<Eigen::Vector3f>& colors,
                                        const Skeleton& skeleton, int size, int margin) {
  if (colors.size() != mesh.n_vertices())
    throw InputError(std::to_string(colors.size()) + " vertex colours for a mesh with " + std::to_string(mesh.n_vertices()) + " vertices");
  LayoutOptions lo;
  lo.size = size;
  lo.margin = margin;
  const Layout layout = compute_layout(mesh, skeleton, lo);
  std::vector<Eigen::Vector4f> corners;
  corners.reserve(3 * mesh.n_faces());
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f)) corners.emplace_back(colors[v.idx()].x(), colors[v.idx()].y(), colors[v.idx()].z(), 1.f);
  const FloatImage painted = render_atlas_values(gl, mesh, layout, corners);
  TexturedMesh out;
  out.texture = Image(painted.width, painted.height, 4, 255);
  for (int y = 0; y < painted.height; ++y)
    for (int x = 0; x < painted.width; ++x)
      for (int k = 0; k < 3; ++k) out.texture.at(x, y)[k] = uint8_t(std::lround(255 * std::clamp(painted.at(x, y)[k], 0.f, 1.f)));
  out.mesh = stm_coordinates(mesh, layout).mesh;
  return out;
}

Eigen::Vector3f sample_texture(const Image& texture, const Eigen::Vector2d& uv) {
  // Texel centres at (i + 0.5) / size; image rows run top to bottom, v bottom to top.
  const double x = uv.x() * texture.width - 0.5, y = (1.0 - uv.y()) * texture.height - 0.5;
  const double fx = std::floor(x), fy = std::floor(y);
  const float ax = float(x - fx), ay = float(y - fy);
  const int x0 = int(fx), y0 = int(fy);
  return (1 - ay) * ((1 - ax) * texel(texture, x0, y0) + ax * texel(texture, x0 + 1, y0)) +
         ay * ((1 - ax) * texel(texture, x0, y0 + 1) + ax * texel(texture, x0 + 1, y0 + 1));
}

std::vector<Eigen::Vector3f> carry_texture_colors(const Mesh& source, const Image& texture,
                                                  const std::vector<SourcePoint>& correspondence) {
  if (!source.has_halfedge_texcoords2D()) throw InputError("the source has no texture coordinates, so its texture cannot be sampled");
  if (texture.width <= 0 || texture.height <= 0 || texture.pixels.empty()) throw InputError("the source's texture is empty");
  std::vector<Eigen::Vector3f> out;
  out.reserve(correspondence.size());
  for (size_t j = 0; j < correspondence.size(); ++j) {
    const Mesh::FaceHandle f = source_face(source, correspondence, j);
    // Corner k of the face (fv_range order) is the vertex its k-th halfedge points to.
    std::array<Mesh::VertexHandle, 3> corner;
    int k = 0;
    for (auto v : source.fv_range(f)) corner[k++] = v;
    Eigen::Vector2d uv = Eigen::Vector2d::Zero();
    for (auto h : source.fh_range(f))
      for (int c = 0; c < 3; ++c)
        if (source.to_vertex_handle(h) == corner[c]) {
          const auto& t = source.texcoord2D(h);
          uv += correspondence[j].barycentric[c] * Eigen::Vector2d(t[0], t[1]);
        }
    out.push_back(sample_texture(texture, uv));
  }
  return out;
}

}  // namespace sdm
