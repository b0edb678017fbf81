#include "libstm/render/render_mesh.h"

#include "libstm/core/errors.h"
#include "libstm/geometry/differential_geometry.h"

#include "libstm/render/gl_objects.h"  // GL prototypes and owning handles
#include "libstm/render/gl_state.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

namespace sdm {

Camera frame_camera(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double azimuth_deg, double elevation_deg,
                    int width, int height, bool orthographic, const Eigen::Matrix3d& frame) {
  if (!(lo.array() <= hi.array()).all() || !lo.allFinite() || !hi.allFinite())
    throw InputError("cannot frame an empty or invalid bounding box");
  if (width <= 0 || height <= 0) throw InputError("image size must be positive");
  const double radius = 0.5 * (hi - lo).norm();
  if (!(radius > 0)) throw InputError("cannot frame a bounding box of zero size");
  const double az = azimuth_deg * M_PI / 180.0, el = elevation_deg * M_PI / 180.0;
  const Eigen::Vector3d local(std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az));
  const Eigen::Vector3d dir = frame * local;

  Camera cam;
  cam.orthographic = orthographic;
  cam.center = 0.5 * (lo + hi);
  // The smaller image dimension spans 30 degrees; the bounding sphere is tangent to its edges.
  const double half_fov = 15.0 * M_PI / 180.0;
  const double distance = radius / std::sin(half_fov);
  cam.eye = cam.center + distance * dir;

  // Look-at with the frame's +y up; straight above or below, +y is the view direction, so use its
  // -z / +z instead.
  const Eigen::Vector3d back = dir;  // camera z axis (camera looks down -z)
  Eigen::Vector3d up = frame * (std::abs(local.y()) > 0.999999 ? Eigen::Vector3d(0, 0, local.y() > 0 ? -1 : 1) : Eigen::Vector3d(0, 1, 0));
  const Eigen::Vector3d right = up.cross(back).normalized();
  up = back.cross(right);
  cam.view.setIdentity();
  cam.view.block<1, 3>(0, 0) = right.transpose();
  cam.view.block<1, 3>(1, 0) = up.transpose();
  cam.view.block<1, 3>(2, 0) = back.transpose();
  cam.view.block<3, 1>(0, 3) = -cam.view.block<3, 3>(0, 0) * cam.eye;

  const double aspect = double(width) / double(height);
  const double near_ = distance - 1.05 * radius, far_ = distance + 1.05 * radius;
  cam.projection.setZero();
  if (orthographic) {
    const double hy = aspect >= 1 ? radius : radius / aspect, hx = hy * aspect;
    cam.projection(0, 0) = 1.0 / hx;
    cam.projection(1, 1) = 1.0 / hy;
    cam.projection(2, 2) = -2.0 / (far_ - near_);
    cam.projection(2, 3) = -(far_ + near_) / (far_ - near_);
    cam.projection(3, 3) = 1.0;
  } else {
    const double t = std::tan(half_fov);
    const double ty = aspect >= 1 ? t : t / aspect, tx = ty * aspect;
    cam.projection(0, 0) = 1.0 / tx;
    cam.projection(1, 1) = 1.0 / ty;
    cam.projection(2, 2) = -(far_ + near_) / (far_ - near_);
    cam.projection(2, 3) = -2.0 * far_ * near_ / (far_ - near_);
    cam.projection(3, 2) = -1.0;
  }
  return cam;
}

Eigen::Matrix3d principal_view_frame(const Mesh& mesh, const std::optional<Eigen::Vector3d>& up) {
  // The surface's exact moments, face by face (a triangle's second moment about the origin is
  // A / 12 (sum v v^T + (sum v)(sum v)^T)), so the axes do not depend on the tessellation; taken
  // about the box centre, for precision far from the origin.
  if (mesh.n_faces() == 0) return up ? up_view_frame(*up) : Eigen::Matrix3d::Identity();
  Eigen::Vector3d lo, hi;
  bounding_box(mesh, lo, hi);
  const Eigen::Vector3d centre = 0.5 * (lo + hi);
  double total = 0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (auto f : mesh.faces()) {
    Eigen::Vector3d v[3];
    int k = 0;
    for (auto x : mesh.fv_range(f)) v[k++] = point(mesh, x) - centre;
    const double area = triangle_area(v[0], v[1], v[2]);
    const Eigen::Vector3d sum = v[0] + v[1] + v[2];
    total += area;
    first += area / 3 * sum;
    second += area / 12 * (v[0] * v[0].transpose() + v[1] * v[1].transpose() + v[2] * v[2].transpose() + sum * sum.transpose());
  }
  if (!(total > 0)) return up ? up_view_frame(*up) : Eigen::Matrix3d::Identity();
  const Eigen::Vector3d mean = first / total;
  const Eigen::Matrix3d moment = second / total - mean * mean.transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(moment);  // eigenvalues ascending
  const Eigen::Vector3d smallest = eig.eigenvectors().col(0), longest = eig.eigenvectors().col(2);
  // Each axis points the way of the world axis it is closest to.
  auto towards_world = [](Eigen::Vector3d a) {
    Eigen::Index k;
    a.cwiseAbs().maxCoeff(&k);
    return a[k] < 0 ? Eigen::Vector3d(-a) : a;
  };
  const bool lying = std::abs(smallest.y()) > std::cos(45.0 * M_PI / 180.0);  // y through the model's thinnest dimension
  Eigen::Matrix3d frame;
  frame.col(1) = up ? up->normalized() : lying ? towards_world(longest) : Eigen::Vector3d::UnitY();
  // Looked at along the shortest axis made square to up, or the middle one where up is the shortest.
  Eigen::Vector3d along = smallest - smallest.dot(frame.col(1)) * frame.col(1);
  if (along.norm() < 0.5) along = eig.eigenvectors().col(1) - eig.eigenvectors().col(1).dot(frame.col(1)) * frame.col(1);
  frame.col(2) = towards_world(along.normalized());
  frame.col(0) = frame.col(1).cross(frame.col(2));
  return frame;
}

Eigen::Matrix3d up_view_frame(const Eigen::Vector3d& up) {
  const Eigen::Vector3d u = up.normalized();
  if (u.y() < -1 + 1e-12) return Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitY(), u).toRotationMatrix();
}

namespace {

// One vertex per triangle corner: uv lives on halfedges and flat normals on faces, so corners
// are not shared. Layout: position (relative to `origin`), normal, uv, colour (the vertex's from
// `colors` when given, else 0; kCornerFloats floats in all). A corner's normal averages
// (area-weighted) the faces around its vertex that bend less than `crease_deg` from its own face,
// so smooth parts look smooth and sharp edges stay sharp.
constexpr int kCornerFloats = 11;

std::vector<float> corner_vertices(const Mesh& mesh, const Eigen::Vector3d& origin, double crease_deg, bool uv,
                                   const std::vector<Eigen::Vector3f>* colors) {
  std::vector<Eigen::Vector3d> face_normal(mesh.n_faces(), Eigen::Vector3d::Zero());  // length = twice the area
  for (auto f : mesh.faces()) {
    auto h = mesh.halfedge_handle(f);
    const Eigen::Vector3d a = point(mesh, mesh.from_vertex_handle(h));
    const Eigen::Vector3d b = point(mesh, mesh.to_vertex_handle(h));
    const Eigen::Vector3d c = point(mesh, mesh.to_vertex_handle(mesh.next_halfedge_handle(h)));
    face_normal[f.idx()] = (b - a).cross(c - a);
  }
  const double cos_crease = std::cos(crease_deg * M_PI / 180.0);
  std::vector<float> out;
  out.reserve(mesh.n_faces() * 3 * kCornerFloats);
  for (auto f : mesh.faces()) {
    const Eigen::Vector3d nf = face_normal[f.idx()];
    const double lf = nf.norm();
    for (auto h : mesh.fh_range(f)) {
      auto v = mesh.to_vertex_handle(h);
      const Eigen::Vector3d p = point(mesh, v) - origin;
      Eigen::Vector3d n = nf;
      if (crease_deg > 0 && lf > 0)
        for (auto g : mesh.vf_range(v)) {
          const Eigen::Vector3d& ng = face_normal[g.idx()];
          const double lg = ng.norm();
          if (g != f && lg > 0 && nf.dot(ng) >= cos_crease * lf * lg) n += ng;
        }
      n = n.norm() > 0 ? n.normalized() : Eigen::Vector3d(0, 0, 1);
      out.insert(out.end(), {float(p.x()), float(p.y()), float(p.z()), float(n.x()), float(n.y()), float(n.z())});
      if (uv) {
        const auto& t = mesh.texcoord2D(h);
        out.insert(out.end(), {float(t[0]), float(t[1])});
      } else {
        out.insert(out.end(), {0.f, 0.f});
      }
      const Eigen::Vector3f c = colors ? (*colors)[size_t(v.idx())] : Eigen::Vector3f::Zero();
      out.insert(out.end(), {c.x(), c.y(), c.z()});
    }
  }
  return out;
}

Eigen::Matrix4f to_float(const Eigen::Matrix4d& m) { return m.cast<float>(); }

}  // namespace

Image render_mesh(GlContext& gl, const Mesh& mesh, const RenderOptions& opt, std::vector<uint8_t>* mask) {
  if (mesh.n_faces() == 0) throw InputError("cannot render a mesh with no faces");
  if (opt.width <= 0 || opt.height <= 0 || opt.width > 16384 || opt.height > 16384)
    throw InputError("image size " + std::to_string(opt.width) + "x" + std::to_string(opt.height) +
                     " is outside 1..16384");
  const bool textured = opt.texture != nullptr;
  if (textured && !mesh.has_halfedge_texcoords2D())
    throw InputError("a texture was given but the mesh has no texture coordinates");

  Eigen::Vector3d lo = opt.bbox_min, hi = opt.bbox_max;
  if (!(lo.array() <= hi.array()).all()) bounding_box(mesh, lo, hi);
  const Camera cam = frame_camera(lo, hi, opt.azimuth_deg, opt.elevation_deg, opt.width, opt.height, opt.orthographic, opt.frame);

  gl.make_current();
  const std::vector<Eigen::Vector3f>* colors = textured ? nullptr : opt.vertex_colors;
  if (colors && colors->size() != mesh.n_vertices())
    throw InputError("render: " + std::to_string(colors->size()) + " vertex colours for " + std::to_string(mesh.n_vertices()) + " vertices");
  const std::vector<float> verts = corner_vertices(mesh, cam.center, opt.flat_shading ? 0.0 : opt.crease_angle_deg, textured, colors);

  Framebuffer fb(opt.width, opt.height, opt.samples);
  const GlBuffer vbo = make_buffer(verts);
  const GlVertexArray vao = make_vertex_array();
  glVertexArrayVertexBuffer(vao.get(), 0, vbo.get(), 0, kCornerFloats * sizeof(float));
  const GLint sizes[4] = {3, 3, 2, 3};
  const GLuint offsets[4] = {0, 3 * sizeof(float), 6 * sizeof(float), 8 * sizeof(float)};
  for (GLuint a = 0; a < 4; ++a) {
    glEnableVertexArrayAttrib(vao.get(), a);
    glVertexArrayAttribFormat(vao.get(), a, sizes[a], GL_FLOAT, GL_FALSE, offsets[a]);
    glVertexArrayAttribBinding(vao.get(), a, 0);
  }
  GlTexture tex;
  if (textured) tex = GlTexture(upload_texture(*opt.texture, true, true));

  const GLuint prog = gl.program("mesh.vert.glsl", "mesh.frag.glsl");
  // Positions are relative to the box centre, so the model-view includes that translation; it is
  // composed in double before the cast to keep precision for meshes far from the origin.
  Eigen::Matrix4d to_center = Eigen::Matrix4d::Identity();
  to_center.block<3, 1>(0, 3) = cam.center;
  const Eigen::Matrix4f model_view = to_float(cam.view * to_center), projection = to_float(cam.projection);

  fb.bind();
  const float transparent[4] = {0, 0, 0, 0};
  set_opaque_depth_state();
  if (fb.samples() > 1) glEnable(GL_MULTISAMPLE);
  fb.clear(transparent);

  glUseProgram(prog);
  glUniformMatrix4fv(glGetUniformLocation(prog, "u_model_view"), 1, GL_FALSE, model_view.data());
  glUniformMatrix4fv(glGetUniformLocation(prog, "u_projection"), 1, GL_FALSE, projection.data());
  glUniform1i(glGetUniformLocation(prog, "u_color_source"), textured ? 1 : colors ? 2 : 0);
  glUniform3f(glGetUniformLocation(prog, "u_color"), opt.color.x(), opt.color.y(), opt.color.z());
  glUniform1i(glGetUniformLocation(prog, "u_lit"), opt.unlit ? 0 : 1);
  glUniform1i(glGetUniformLocation(prog, "u_orthographic"), opt.orthographic ? 1 : 0);
  glUniform1f(glGetUniformLocation(prog, "u_ambient"), float(opt.ambient));
  glUniform1i(glGetUniformLocation(prog, "u_texture"), 0);
  glBindTextureUnit(0, tex.get());
  glBindVertexArray(vao.get());
  glDrawArrays(GL_TRIANGLES, 0, GLsizei(verts.size() / kCornerFloats));
  glBindVertexArray(0);
  glBindTextureUnit(0, 0);
  glUseProgram(0);
  check_gl("render_mesh");

  if (opt.overlay) {
    opt.overlay(cam);
    gl.make_current();
    fb.bind();
  }
  Image img = fb.read_rgba8();
  glBindFramebuffer(GL_FRAMEBUFFER, 0);

  composite_over_background(img, opt.background, mask);
  return img;
}

void composite_over_background(Image& img, const std::array<uint8_t, 4>& background, std::vector<uint8_t>* mask) {
  if (mask) mask->assign(size_t(img.width) * img.height, 0);
  for (size_t i = 0, n = size_t(img.width) * img.height; i < n; ++i) {
    uint8_t* p = &img.pixels[i * 4];
    const int a = p[3];
    for (int k = 0; k < 3; ++k) p[k] = uint8_t(std::min(255, p[k] + (background[k] * (255 - a) + 127) / 255));
    p[3] = uint8_t(std::min(255, a + (background[3] * (255 - a) + 127) / 255));
    if (mask && a >= 128) (*mask)[i] = 255;
  }
}

}  // namespace sdm
