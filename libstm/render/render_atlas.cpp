#include "libstm/render/render_atlas.h"

#include "libstm/geometry/capsule_uv.h"
#include "libstm/core/errors.h"
#include "libstm/layout/assign_layout_faces.h"
#include "libstm/layout/segments.h"

#include "libstm/render/gl_objects.h"  // GL prototypes and owning handles
#include "libstm/render/gl_state.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace sdm {

namespace {

constexpr int kFloats = 11;  // atlas x, y, depth; clip rectangle (4); value (4)
constexpr float kOwnDepth = 0.25f, kNeighbourDepth = 0.75f;

// Local (u, v) of a triangle in segment s, its angles unwrapped against its first corner off the
// axis; corners on the axis (a pole: no angle) take the mean of the others.
std::array<Eigen::Vector2d, 3> local_triangle(const Layout& L, int s, const std::array<Eigen::Vector3d, 3>& p) {
  const LayoutSegment& g = L.segments[s];
  const CapsuleFrame f = capsule_frame(L, s);
  const double h = g.h;
  const double eps = 1e-9 * std::max(g.radius + g.length, 1e-300);
  std::array<CapsuleUV, 3> c;
  for (int k = 0; k < 3; ++k) c[k] = capsule_uv(f, g.w, h, g.d, p[k]);
  std::array<double, 3> u{c[0].u, c[1].u, c[2].u};
  int ref = -1, n = 0;
  double mean = 0;
  for (int k = 0; k < 3; ++k) {
    if (c[k].rho <= eps) continue;
    if (ref < 0) ref = k;
    u[k] -= h * std::round((u[k] - u[ref]) / h);
    mean += u[k];
    ++n;
  }
  if (n > 0) mean /= n;
  for (int k = 0; k < 3; ++k)
    if (c[k].rho <= eps) u[k] = mean;
  return {Eigen::Vector2d(u[0], c[0].v), Eigen::Vector2d(u[1], c[1].v), Eigen::Vector2d(u[2], c[2].v)};
}

// The triangles of the atlas pass, kFloats per corner. value(f, k) is the attribute of corner k.
template <class Value>
std::vector<float> atlas_vertices(const Mesh& mesh, const Layout& L, const std::vector<int>& fs, Value value) {
  const int ns = int(L.segments.size());
  std::vector<std::vector<int>> node_segments(L.skeleton.nodes.size());
  for (int s = 0; s < ns; ++s) {
    node_segments[L.segments[s].a].push_back(s);
    if (L.segments[s].b != L.segments[s].a) node_segments[L.segments[s].b].push_back(s);
  }
  std::vector<float> out;
  out.reserve(mesh.n_faces() * 3 * kFloats * 3);
  std::vector<int> targets;
  for (auto f : mesh.faces()) {
    std::array<Eigen::Vector3d, 3> p;
    std::array<int, 3> vi{};
    int k = 0;
    for (auto v : mesh.fv_range(f)) p[k] = point(mesh, v), vi[k++] = v.idx();
    const int own = fs[f.idx()];
    // This face's own segment, then every segment it neighbours (behind the owners there).
    targets.assign(1, own);
    for (int o : L.segments[own].neighbours_a) targets.push_back(o);
    for (int o : L.segments[own].neighbours_b) targets.push_back(o);
    for (int v : vi)
      for (int o : node_segments[L.skeleton.vertex_node[v]]) targets.push_back(o);
    std::sort(targets.begin() + 1, targets.end());
    targets.erase(std::unique(targets.begin() + 1, targets.end()), targets.end());
    for (size_t i = 0; i < targets.size(); ++i) {
      const int s = targets[i];
      if (i > 0 && s == own) continue;
      const LayoutSegment& g = L.segments[s];
      const auto local = local_triangle(L, s, p);
      double lo = local[0].x(), hi = lo;
      for (const auto& q : local) lo = std::min(lo, q.x()), hi = std::max(hi, q.x());
      // A neighbour's triangle that wraps around this axis has no sensible place here.
      if (i > 0 && hi - lo > 0.5 * g.h) continue;
      const double m = L.margin;
      const float ex = float(g.rotated ? g.h : g.w), ey = float(g.rotated ? g.w : g.h);
      const float clip[4] = {float(g.x - m), float(g.y - m), float(g.x + ex + m), float(g.y + ey + m)};
      const float depth = i == 0 ? kOwnDepth : kNeighbourDepth;
      for (int shift = -1; shift <= 1; ++shift) {
        const double du = shift * double(g.h);
        if (hi + du < -m || lo + du > g.h + m) continue;
        for (int c = 0; c < 3; ++c) {
          const Eigen::Vector2d a = local_to_atlas(g, local[c].x() + du, local[c].y());
          const Eigen::Vector4f val = value(f.idx(), c);
          out.insert(out.end(), {float(a.x()), float(a.y()), depth, clip[0], clip[1], clip[2], clip[3], val[0], val[1],
                                 val[2], val[3]});
        }
      }
    }
  }
  return out;
}

struct AtlasPass {
  std::vector<uint8_t> rgba;   // size^2 * 4, rows top to bottom
  std::vector<float> values;   // size^2 * 4 (float mode)
};

AtlasPass draw_atlas_pass(GlContext& gl, const Layout& L, const std::vector<float>& verts, const Image* source) {
  const int S = L.size;
  gl.make_current();
  GLint dims[2] = {0, 0}, max_tex = 0;
  glGetIntegerv(GL_MAX_VIEWPORT_DIMS, dims);
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_tex);
  if (S <= 0 || S > dims[0] || S > dims[1] || S > max_tex)
    throw InputError("atlas of " + std::to_string(S) + "^2 texels exceeds the GL limits (" + std::to_string(std::min(dims[0], max_tex)) + ")");
  const bool values = source == nullptr;
  Framebuffer fb(S, S, 1, values);
  const GlBuffer vbo = make_buffer(verts);
  const GlVertexArray vao = make_vertex_array();
  glVertexArrayVertexBuffer(vao.get(), 0, vbo.get(), 0, kFloats * sizeof(float));
  const GLint sizes[3] = {3, 4, 4};
  const GLuint offsets[3] = {0, 3 * sizeof(float), 7 * sizeof(float)};
  for (GLuint a = 0; a < 3; ++a) {
    glEnableVertexArrayAttrib(vao.get(), a);
    glVertexArrayAttribFormat(vao.get(), a, sizes[a], GL_FLOAT, GL_FALSE, offsets[a]);
    glVertexArrayAttribBinding(vao.get(), a, 0);
  }
  GlTexture tex;
  if (source) {
    tex = GlTexture(upload_texture(*source, true, false));
  } else {
    const uint8_t white[4] = {255, 255, 255, 255};
    tex = make_texture(GL_TEXTURE_2D);
    glTextureStorage2D(tex.get(), 1, GL_RGBA8, 1, 1);
    glTextureSubImage2D(tex.get(), 0, 0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, white);
  }
  const GLuint prog = gl.program("atlas.vert.glsl", "atlas.frag.glsl");
  fb.bind();
  set_opaque_depth_state();
  glDisable(GL_MULTISAMPLE);
  const float zero[4] = {0, 0, 0, 0};
  fb.clear(zero, zero);
  glUseProgram(prog);
  glUniform1f(glGetUniformLocation(prog, "u_size"), float(S));
  glUniform1i(glGetUniformLocation(prog, "u_mode"), values ? 1 : 0);
  glUniform1i(glGetUniformLocation(prog, "u_source"), 0);
  glBindTextureUnit(0, tex.get());
  glBindVertexArray(vao.get());
  glDrawArrays(GL_TRIANGLES, 0, GLsizei(verts.size() / kFloats));
  glBindVertexArray(0);
  glBindTextureUnit(0, 0);
  glUseProgram(0);
  check_gl("render_atlas");
  AtlasPass r;
  r.rgba = fb.read_rgba8().pixels;
  if (values) r.values = fb.read_float().pixels;
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  return r;
}

std::vector<int> checked_faces(const Mesh& mesh, const Layout& L) {
  if (L.segments.empty()) throw InputError("the layout has no segment");
  return assign_faces(mesh, L);  // throws when the skeleton is not this mesh's
}

std::vector<float> coverage_weights(const std::vector<uint8_t>& rgba, std::vector<uint8_t>* covered) {
  const size_t n = rgba.size() / 4;
  std::vector<float> w(n);
  if (covered) covered->assign(n, 0);
  for (size_t i = 0; i < n; ++i) {
    w[i] = rgba[i * 4 + 3] > 0 ? 1.f : 0.f;
    if (covered && w[i] > 0) (*covered)[i] = 255;
  }
  return w;
}

}  // namespace

void push_pull_fill(std::vector<float>& values, const std::vector<float>& weight, int W, int H, int C) {
  if (W <= 0 || H <= 0 || C <= 0 || values.size() != size_t(W) * H * C || weight.size() != size_t(W) * H)
    throw InputError("push_pull_fill: inconsistent image");
  // Pull: each level is the weight-averaged 2x2 reduction of the one below (weights summed, capped at 1).
  struct Level {
    int w, h;
    std::vector<float> v, wt;
  };
  std::vector<Level> levels;
  levels.push_back({W, H, values, weight});
  while (levels.back().w > 1 || levels.back().h > 1) {
    const Level& f = levels.back();
    Level c{(f.w + 1) / 2, (f.h + 1) / 2, {}, {}};
    c.v.assign(size_t(c.w) * c.h * C, 0.f);
    c.wt.assign(size_t(c.w) * c.h, 0.f);
    for (int y = 0; y < c.h; ++y)
      for (int x = 0; x < c.w; ++x) {
        float sw = 0;
        std::vector<float> acc(C, 0.f);
        for (int dy = 0; dy < 2; ++dy)
          for (int dx = 0; dx < 2; ++dx) {
            const int fx = 2 * x + dx, fy = 2 * y + dy;
            if (fx >= f.w || fy >= f.h) continue;
            const size_t i = size_t(fy) * f.w + fx;
            const float wi = f.wt[i];
            if (wi <= 0) continue;
            sw += wi;
            for (int k = 0; k < C; ++k) acc[k] += wi * f.v[i * C + k];
          }
        const size_t j = size_t(y) * c.w + x;
        if (sw > 0)
          for (int k = 0; k < C; ++k) c.v[j * C + k] = acc[k] / sw;
        c.wt[j] = std::min(sw, 1.f);
      }
    levels.push_back(std::move(c));
  }
  // Push: from coarse to fine, an empty texel (or the empty share of a partly covered coarse one)
  // takes the bilinear interpolation of the level above.
  for (int l = int(levels.size()) - 2; l >= 0; --l) {
    Level& f = levels[l];
    const Level& c = levels[l + 1];
    for (int y = 0; y < f.h; ++y)
      for (int x = 0; x < f.w; ++x) {
        const size_t i = size_t(y) * f.w + x;
        const float wi = std::min(f.wt[i], 1.f);
        if (wi >= 1) continue;
        // Texel centre in the coarse level's texel units.
        const float cx = std::clamp((x + 0.5f) * 0.5f - 0.5f, 0.f, float(c.w - 1));
        const float cy = std::clamp((y + 0.5f) * 0.5f - 0.5f, 0.f, float(c.h - 1));
        const int x0 = int(cx), y0 = int(cy), x1 = std::min(x0 + 1, c.w - 1), y1 = std::min(y0 + 1, c.h - 1);
        const float tx = cx - x0, ty = cy - y0;
        for (int k = 0; k < C; ++k) {
          const float up = (1 - tx) * (1 - ty) * c.v[(size_t(y0) * c.w + x0) * C + k] + tx * (1 - ty) * c.v[(size_t(y0) * c.w + x1) * C + k] +
                           (1 - tx) * ty * c.v[(size_t(y1) * c.w + x0) * C + k] + tx * ty * c.v[(size_t(y1) * c.w + x1) * C + k];
          f.v[i * C + k] = wi * f.v[i * C + k] + (1 - wi) * up;
        }
        f.wt[i] = 1;
      }
  }
  values = std::move(levels[0].v);
}

Image render_atlas(GlContext& gl, const Mesh& mesh, const Layout& L, const Image& source, const AtlasOptions& opt,
                   std::vector<uint8_t>* covered) {
  if (!mesh.has_halfedge_texcoords2D()) throw InputError("the mesh has no texture coordinates, so there is no texture to remap");
  const std::vector<int> fs = checked_faces(mesh, L);
  if (opt.progress) opt.progress("drawing " + std::to_string(mesh.n_faces()) + " faces into a " + std::to_string(L.size) + "^2 atlas");
  // Each corner's uv: the halfedge pointing at it.
  std::vector<Eigen::Vector4f> uv(mesh.n_faces() * 3, Eigen::Vector4f::Zero());
  for (auto f : mesh.faces()) {
    int k = 0;
    for (auto v : mesh.fv_range(f)) {
      for (auto h : mesh.fh_range(f))
        if (mesh.to_vertex_handle(h) == v) {
          const auto& t = mesh.texcoord2D(h);
          uv[size_t(f.idx()) * 3 + k] = Eigen::Vector4f(float(t[0]), float(t[1]), 0.f, 0.f);
        }
      ++k;
    }
  }
  const std::vector<float> verts = atlas_vertices(mesh, L, fs, [&](int f, int k) { return uv[size_t(f) * 3 + k]; });
  AtlasPass pass = draw_atlas_pass(gl, L, verts, &source);
  const int S = L.size;
  const std::vector<float> w = coverage_weights(pass.rgba, covered);
  Image img(S, S, 4);
  if (opt.fill) {
    if (opt.progress) opt.progress("filling uncovered texels (push-pull)");
    std::vector<float> v(size_t(S) * S * 3);
    for (size_t i = 0; i < w.size(); ++i)
      for (int k = 0; k < 3; ++k) v[i * 3 + k] = pass.rgba[i * 4 + k];
    push_pull_fill(v, w, S, S, 3);
    for (size_t i = 0; i < w.size(); ++i) {
      for (int k = 0; k < 3; ++k) img.pixels[i * 4 + k] = uint8_t(std::clamp(std::lround(v[i * 3 + k]), 0L, 255L));
      img.pixels[i * 4 + 3] = 255;
    }
  } else {
    img.pixels = pass.rgba;
    for (size_t i = 0; i < w.size(); ++i) img.pixels[i * 4 + 3] = w[i] > 0 ? 255 : 0;
  }
  return img;
}

FloatImage render_atlas_values(GlContext& gl, const Mesh& mesh, const Layout& L, const std::vector<Eigen::Vector4f>& corner_values,
                               const AtlasOptions& opt, std::vector<uint8_t>* covered) {
  if (corner_values.size() != mesh.n_faces() * 3)
    throw InputError("got " + std::to_string(corner_values.size()) + " corner values for " + std::to_string(mesh.n_faces()) + " faces");
  const std::vector<int> fs = checked_faces(mesh, L);
  const std::vector<float> verts = atlas_vertices(mesh, L, fs, [&](int f, int k) { return corner_values[size_t(f) * 3 + k]; });
  AtlasPass pass = draw_atlas_pass(gl, L, verts, nullptr);
  const int S = L.size;
  const std::vector<float> w = coverage_weights(pass.rgba, covered);
  FloatImage img(S, S, 4);
  img.pixels = std::move(pass.values);
  if (opt.fill) push_pull_fill(img.pixels, w, S, S, 4);
  return img;
}

}  // namespace sdm
