#include "libstm/render/render_stm.h"

#include "libstm/core/errors.h"
#include "libstm/layout/segments.h"

#include "libstm/render/gl_objects.h"  // GL prototypes and owning handles
#include "libstm/render/gl_state.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace sdm {
namespace {

// Throws InputError for what render_stm refuses (see the header).
void check_stm_inputs(const Mesh& mesh, const Layout& L, const Image& atlas, const RenderOptions& opt) {
  if (mesh.n_faces() == 0) throw InputError("cannot render a mesh with no faces");
  if (opt.width <= 0 || opt.height <= 0 || opt.width > 16384 || opt.height > 16384)
    throw InputError("image size " + std::to_string(opt.width) + "x" + std::to_string(opt.height) + " is outside 1..16384");
  if (L.skeleton.vertex_node.size() != mesh.n_vertices())
    throw InputError("the layout's skeleton maps " + std::to_string(L.skeleton.vertex_node.size()) + " vertices but the mesh has " +
                     std::to_string(mesh.n_vertices()) + " (layout of another mesh?)");
  if (L.segments.empty()) throw InputError("the layout has no segment");
  if (atlas.width != L.size || atlas.height != L.size || atlas.pixels.size() != size_t(atlas.width) * atlas.height * atlas.channels)
    throw InputError("the atlas is " + std::to_string(atlas.width) + "x" + std::to_string(atlas.height) + " but the layout needs " +
                     std::to_string(L.size) + "x" + std::to_string(L.size));
  for (int n : L.skeleton.vertex_node)
    if (n < 0 || n >= int(L.skeleton.nodes.size())) throw InputError("the layout's skeleton maps a vertex to node " + std::to_string(n));
}

// What the vertex stage reads: per vertex its position relative to the framing centre `o` and its
// area-weighted normal (6 floats), and its (node, orientation); the triangles as indices.
struct StmVertices {
  std::vector<float> verts;
  std::vector<int> nodes;
  std::vector<GLuint> index;
};

StmVertices stm_vertices(const Mesh& mesh, const Layout& L, const Eigen::Vector3d& o) {
  StmVertices r;
  // Vertices shared by their faces: no uv, so nothing is split at the seam.
  std::vector<Eigen::Vector3d> normal(mesh.n_vertices(), Eigen::Vector3d::Zero());
  std::vector<GLuint>& index = r.index;
  index.reserve(mesh.n_faces() * 3);
  for (auto f : mesh.faces()) {
    Eigen::Vector3d p[3];
    int k = 0;
    for (auto v : mesh.fv_range(f)) {
      p[k++] = point(mesh, v);
      index.push_back(GLuint(v.idx()));
    }
    const Eigen::Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]);  // area weighted
    for (int j = 0; j < 3; ++j) normal[index[index.size() - 3 + j]] += n;
  }
  r.verts.reserve(mesh.n_vertices() * 6);
  for (auto v : mesh.vertices()) {
    const Eigen::Vector3d p = point(mesh, v) - o;
    const Eigen::Vector3d n = normal[v.idx()].norm() > 0 ? normal[v.idx()].normalized() : Eigen::Vector3d(0, 0, 1);
    r.verts.insert(r.verts.end(), {float(p.x()), float(p.y()), float(p.z()), float(n.x()), float(n.y()), float(n.z())});
  }
  // Per vertex: its skeleton node and the orientation of its part, which assign_faces' rule needs
  // (a vertex's faces all lie in one part: parts are connected through shared edges, and OpenMesh
  // cannot hold a vertex shared by two fans). A mesh from load_mesh is outward already, but a
  // library caller may pass one wound inside out.
  const std::vector<int> face_orient = face_orientation(mesh);
  std::vector<int> vertex_orient(mesh.n_vertices(), 1);
  for (auto f : mesh.faces())
    for (auto v : mesh.fv_range(f)) vertex_orient[v.idx()] = face_orient[f.idx()];
  r.nodes.reserve(2 * mesh.n_vertices());
  for (size_t v = 0; v < mesh.n_vertices(); ++v) r.nodes.insert(r.nodes.end(), {L.skeleton.vertex_node[v], vertex_orient[v]});
  return r;
}

// Segments: 6 RGBA32F texels each: (a, node a), (b, node b) (a and b relative to the framing centre
// o), (e1, extension past a), (e2, extension past b), rect, (d, rotated, radius). Node indices are
// exact in float up to 2^24.
std::vector<float> segment_texels(const Layout& L, const Eigen::Vector3d& o) {
  std::vector<float> seg;
  for (size_t s = 0; s < L.segments.size(); ++s) {
    const LayoutSegment& g = L.segments[s];
    const Eigen::Vector3d a = L.skeleton.nodes[g.a] - o, b = L.skeleton.nodes[g.b] - o;
    seg.insert(seg.end(), {float(a.x()), float(a.y()), float(a.z()), float(g.a), float(b.x()), float(b.y()), float(b.z()),
                           float(g.b), float(g.e1.x()), float(g.e1.y()), float(g.e1.z()), float(g.extend_a), float(g.e2.x()),
                           float(g.e2.y()), float(g.e2.z()), float(g.extend_b), float(g.x), float(g.y), float(g.w), float(g.h),
                           float(g.d), g.rotated ? 1.f : 0.f, float(g.radius), 0.f});
  }
  return seg;
}

// Node -> incident segments, offsets first (absolute positions in the same buffer).
std::vector<GLint> node_incidence(const Layout& L) {
  const int nn = int(L.skeleton.nodes.size());
  std::vector<std::vector<int>> node_segments(nn);
  for (size_t s = 0; s < L.segments.size(); ++s) {
    node_segments[L.segments[s].a].push_back(int(s));
    if (L.segments[s].b != L.segments[s].a) node_segments[L.segments[s].b].push_back(int(s));
  }
  std::vector<GLint> incidence(size_t(nn) + 1);
  for (int n = 0, at = nn + 1; n <= nn; ++n) {
    incidence[n] = at;
    if (n < nn) at += int(node_segments[n].size());
  }
  for (int n = 0; n < nn; ++n) incidence.insert(incidence.end(), node_segments[n].begin(), node_segments[n].end());
  return incidence;
}

// The GL objects of the STM pass: the vertex array (positions and normals at binding 0,
// attributes 0-1; node and orientation at binding 1, attributes 2-3; the triangles' indices) and
// the textures of units 0-2 (atlas, segments, incidence).
struct StmObjects {
  GlBuffer vertices, nodes, indices, segments, incidence;
  GlVertexArray vao;
  GlTexture atlas, segment_texture, incidence_texture;
};

StmObjects upload_stm(const StmVertices& v, const std::vector<float>& seg, const std::vector<GLint>& incidence, const Image& atlas) {
  StmObjects g;
  g.vertices = make_buffer(v.verts);
  g.nodes = make_buffer(v.nodes);
  g.indices = make_buffer(v.index);
  g.segments = make_buffer(seg);
  g.incidence = make_buffer(incidence);
  g.vao = make_vertex_array();
  const GLuint vao = g.vao.get();
  glVertexArrayVertexBuffer(vao, 0, g.vertices.get(), 0, 6 * sizeof(float));
  glVertexArrayVertexBuffer(vao, 1, g.nodes.get(), 0, 2 * sizeof(int));
  glVertexArrayElementBuffer(vao, g.indices.get());
  for (GLuint a = 0; a < 2; ++a) {
    glEnableVertexArrayAttrib(vao, a);
    glVertexArrayAttribFormat(vao, a, 3, GL_FLOAT, GL_FALSE, a * 3 * sizeof(float));
    glVertexArrayAttribBinding(vao, a, 0);
  }
  for (GLuint a = 2; a < 4; ++a) {
    glEnableVertexArrayAttrib(vao, a);
    glVertexArrayAttribIFormat(vao, a, 1, GL_INT, (a - 2) * sizeof(int));
    glVertexArrayAttribBinding(vao, a, 1);
  }
  g.atlas = GlTexture(upload_texture(atlas, false, false));  // clamped: margins, not wrapping, make filtering right
  g.segment_texture = make_texture(GL_TEXTURE_BUFFER);
  g.incidence_texture = make_texture(GL_TEXTURE_BUFFER);
  glTextureBuffer(g.segment_texture.get(), GL_RGBA32F, g.segments.get());
  glTextureBuffer(g.incidence_texture.get(), GL_R32I, g.incidence.get());
  return g;
}

void set_stm_uniforms(GLuint prog, const Camera& cam, const Layout& L, const RenderOptions& opt) {
  Eigen::Matrix4d to_center = Eigen::Matrix4d::Identity();
  to_center.block<3, 1>(0, 3) = cam.center;
  const Eigen::Matrix4f model_view = (cam.view * to_center).cast<float>(), projection = cam.projection.cast<float>();
  glUseProgram(prog);
  glUniformMatrix4fv(glGetUniformLocation(prog, "u_model_view"), 1, GL_FALSE, model_view.data());
  glUniformMatrix4fv(glGetUniformLocation(prog, "u_projection"), 1, GL_FALSE, projection.data());
  glUniform1i(glGetUniformLocation(prog, "u_atlas"), 0);
  glUniform1i(glGetUniformLocation(prog, "u_segments"), 1);
  glUniform1i(glGetUniformLocation(prog, "u_nodes"), 2);
  glUniform1i(glGetUniformLocation(prog, "u_segment_count"), GLint(L.segments.size()));
  glUniform1f(glGetUniformLocation(prog, "u_size"), float(L.size));
  glUniform1i(glGetUniformLocation(prog, "u_flat"), opt.flat_shading ? 1 : 0);
  glUniform1i(glGetUniformLocation(prog, "u_second_pass"), L.assignment >= 2 ? 1 : 0);
  glUniform1i(glGetUniformLocation(prog, "u_lit"), opt.unlit ? 0 : 1);
  glUniform1i(glGetUniformLocation(prog, "u_orthographic"), opt.orthographic ? 1 : 0);
  glUniform1f(glGetUniformLocation(prog, "u_ambient"), float(opt.ambient));
}

// One draw of the STM pass into fb; `output` selects what the fragment shader writes (0: the
// shaded colour, 1: coordinates, 2: positions; see StmRenderProbe).
void draw_stm_pass(Framebuffer& fb, GLuint prog, GLuint vao, size_t index_count, int output) {
  fb.bind();
  set_opaque_depth_state();
  if (fb.samples() > 1) glEnable(GL_MULTISAMPLE); else glDisable(GL_MULTISAMPLE);
  const float transparent[4] = {0, 0, 0, 0};
  fb.clear(transparent, transparent);
  glUseProgram(prog);
  glUniform1i(glGetUniformLocation(prog, "u_output"), output);
  glBindVertexArray(vao);
  glDrawElements(GL_TRIANGLES, GLsizei(index_count), GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
  check_gl("render_stm");
}

// The probe passes: single-sample, coordinates then positions, the positions back in model
// coordinates (in double for the offset o).
void read_probe(Framebuffer& pf, GLuint prog, GLuint vao, size_t index_count, const Eigen::Vector3d& o, StmRenderProbe& probe) {
  draw_stm_pass(pf, prog, vao, index_count, 1);
  probe.coordinates = pf.read_float();
  draw_stm_pass(pf, prog, vao, index_count, 2);
  probe.positions = pf.read_float();
  for (size_t i = 0, n = size_t(pf.width()) * pf.height(); i < n; ++i) {
    float* p = &probe.positions.pixels[i * 4];
    if (p[3] > 0)
      for (int k = 0; k < 3; ++k) p[k] = float(double(p[k]) + o[k]);
  }
}

}  // namespace

Image render_stm(GlContext& gl, const Mesh& mesh, const Layout& L, const Image& atlas, const RenderOptions& opt,
                 std::vector<uint8_t>* mask, StmRenderProbe* probe) {
  check_stm_inputs(mesh, L, atlas, opt);
  Eigen::Vector3d lo = opt.bbox_min, hi = opt.bbox_max;
  if (!(lo.array() <= hi.array()).all()) bounding_box(mesh, lo, hi);
  const Camera cam = frame_camera(lo, hi, opt.azimuth_deg, opt.elevation_deg, opt.width, opt.height, opt.orthographic, opt.frame);
  const Eigen::Vector3d& o = cam.center;
  const StmVertices vertices = stm_vertices(mesh, L, o);
  const std::vector<float> seg = segment_texels(L, o);
  const std::vector<GLint> incidence = node_incidence(L);

  gl.make_current();
  GLint max_tex = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_tex);
  if (atlas.width > max_tex) throw InputError("atlas of " + std::to_string(atlas.width) + "^2 exceeds the GL limit of " + std::to_string(max_tex));
  const StmObjects g = upload_stm(vertices, seg, incidence, atlas);
  // The STM pass has a geometry stage: it chooses each triangle's segment (DESIGN 4.7).
  const GLuint prog = gl.program("stm.vert.glsl", "stm.frag.glsl", "stm.geom.glsl");
  set_stm_uniforms(prog, cam, L, opt);
  glBindTextureUnit(0, g.atlas.get());
  glBindTextureUnit(1, g.segment_texture.get());
  glBindTextureUnit(2, g.incidence_texture.get());

  Framebuffer fb(opt.width, opt.height, opt.samples);
  draw_stm_pass(fb, prog, g.vao.get(), vertices.index.size(), 0);
  Image img = fb.read_rgba8();
  if (probe) {
    Framebuffer pf(opt.width, opt.height, 1, true);
    read_probe(pf, prog, g.vao.get(), vertices.index.size(), o, *probe);
  }
  glBindTextureUnit(0, 0);
  glBindTextureUnit(1, 0);
  glBindTextureUnit(2, 0);
  glUseProgram(0);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);

  composite_over_background(img, opt.background, mask);
  return img;
}

}  // namespace sdm
