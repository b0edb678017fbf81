#include "libstm/mesh/gltf_io.h"
#include "libstm/mesh/gltf_io_internal.h"

#include "libstm/core/atomic_file.h"
#include "libstm/core/errors.h"
#include "libstm/core/input_file.h"
#include "libstm/core/limits.h"
#include "libstm/mesh/check_mesh_file.h"

#include <stb/stb_image.h>
#include <algorithm>
#include <cmath>
#include <climits>
#include <cstring>
#include <filesystem>
#include <map>
#include <sstream>

namespace sdm {
namespace gltf_internal {

Eigen::Affine3d node_transform(const tinygltf::Node& n) {
  Eigen::Affine3d t = Eigen::Affine3d::Identity();
  if (n.matrix.size() == 16) {
    Eigen::Matrix4d m;
    for (int i = 0; i < 16; ++i) m(i % 4, i / 4) = n.matrix[i];  // column-major
    t.matrix() = m;
    return t;
  }
  if (n.translation.size() == 3) t.translate(Eigen::Vector3d(n.translation[0], n.translation[1], n.translation[2]));
  if (n.rotation.size() == 4) t.rotate(Eigen::Quaterniond(n.rotation[3], n.rotation[0], n.rotation[1], n.rotation[2]).normalized());
  if (n.scale.size() == 3) t.scale(Eigen::Vector3d(n.scale[0], n.scale[1], n.scale[2]));
  return t;
}

}  // namespace gltf_internal
namespace {

using gltf_internal::AccessorView;
using gltf_internal::node_transform;
namespace fs = std::filesystem;

// Triangles one file may place (instancing multiplies what the buffers hold): 20 million, ten
// times the largest meshes sdm is benchmarked on.
constexpr size_t kMaxTriangles = 20000000;

struct Reader {
  const tinygltf::Model& model;
  std::string path;
  GltfScene out;
  std::map<std::array<double, 3>, int> weld;
  std::vector<Eigen::Vector2d> uv;  // per corner, while every primitive has TEXCOORD_0
  bool all_uv = true;
  int textured_material = -1;
  std::vector<char> visited;  // per node: glTF's node hierarchy is a tree (one parent at most)
  std::vector<Eigen::Vector3f> colors;  // per point (sRGB in [0, 1]; black where no COLOR_0 gives one)
  bool any_color = false;
  gltf_internal::VerticesRead on_vertices;  // told of each primitive's points, when set

  // The COLOR_0 of each of the primitive's vertices onto its point (the first vertex welded there
  // gives it), turned from glTF's linear values to the sRGB ones PLY and OBJ colours hold.
  void vertex_colors(const tinygltf::Primitive& p, const std::vector<int>& point, const std::vector<char>& added, const std::string& what) {
    colors.resize(out.soup.points.size(), Eigen::Vector3f::Zero());
    const auto col = p.attributes.find("COLOR_0");
    if (col == p.attributes.end()) return;
    const AccessorView C(model, col->second, what);
    if (C.count() != point.size() || (C.components() != 3 && C.components() != 4)) throw InputError(what + ": COLOR_0 does not match POSITION");
    auto srgb = [](double x) {
      x = std::clamp(x, 0.0, 1.0);
      return float(x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1 / 2.4) - 0.055);
    };
    for (size_t i = 0; i < point.size(); ++i)
      if (added[i]) colors[size_t(point[i])] = {srgb(C.get(i, 0)), srgb(C.get(i, 1)), srgb(C.get(i, 2))};
    any_color = true;
  }

  void primitive(const tinygltf::Primitive& p, const Eigen::Affine3d& t, int node_index) {
    const std::string what = "glTF " + path;
    if (p.mode != TINYGLTF_MODE_TRIANGLES)
      throw InputError(what + ": a primitive of mode " + std::to_string(p.mode) + " (only triangle lists, mode 4, are read)");
    const auto pos = p.attributes.find("POSITION");
    if (pos == p.attributes.end()) throw InputError(what + ": a primitive without POSITION");
    const AccessorView P(model, pos->second, what);
    if (P.components() != 3 || model.accessors[pos->second].componentType != TINYGLTF_COMPONENT_TYPE_FLOAT)
      throw InputError(what + ": POSITION is not a float VEC3 accessor");
    std::vector<int> point(P.count());
    std::vector<char> added_here(P.count(), 0);
    for (size_t i = 0; i < P.count(); ++i) {
      const Eigen::Vector3d x = t * Eigen::Vector3d(P.get(i, 0), P.get(i, 1), P.get(i, 2));
      if (!(x.cwiseAbs().maxCoeff() <= kMaxCoordinate))  // NaN too
        throw InputError(what + ": its node transforms place a vertex at (" + std::to_string(x.x()) + ", " + std::to_string(x.y()) +
                         ", " + std::to_string(x.z()) + "), beyond the float range sdm reads");
      const auto [it, added] = weld.emplace(std::array<double, 3>{x.x(), x.y(), x.z()}, int(out.soup.points.size()));
      if (added) out.soup.points.push_back(x);
      point[i] = it->second, added_here[i] = added;
    }
    vertex_colors(p, point, added_here, what);
    if (on_vertices) on_vertices(node_index, p, point);
    std::vector<size_t> corners;
    if (p.indices >= 0) {
      const AccessorView I(model, p.indices, what);
      const int type = model.accessors[p.indices].componentType;
      if (I.components() != 1 || (type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
                                  type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT))
        throw InputError(what + ": indices must be unsigned byte, short or int scalars (component type " + std::to_string(type) + ")");
      for (size_t i = 0; i < I.count(); ++i) corners.push_back(size_t(I.get(i, 0)));
    } else {
      for (size_t i = 0; i < P.count(); ++i) corners.push_back(i);
    }
    if (corners.size() % 3) throw InputError(what + ": a triangle list of " + std::to_string(corners.size()) + " indices (not a multiple of 3)");
    if (out.soup.triangles.size() + corners.size() / 3 > kMaxTriangles)
      throw InputError(what + ": its nodes place more than " + std::to_string(kMaxTriangles) +
                       " triangles (meshes instanced many times); sdm reads at most that many");
    for (size_t c : corners)
      if (c >= P.count()) throw InputError(what + ": index " + std::to_string(c) + " beyond the primitive's " + std::to_string(P.count()) + " vertices");
    const auto tex = p.attributes.find("TEXCOORD_0");
    all_uv = all_uv && tex != p.attributes.end();
    if (all_uv) {
      const AccessorView T(model, tex->second, what);
      if (T.count() != P.count() || T.components() != 2) throw InputError(what + ": TEXCOORD_0 does not match POSITION");
      for (size_t c : corners) uv.emplace_back(T.get(c, 0), 1.0 - T.get(c, 1));
      if (textured_material < 0 && p.material >= 0) textured_material = p.material;
    }
    for (size_t k = 0; k < corners.size(); k += 3)
      out.soup.triangles.push_back({point[corners[k]], point[corners[k + 1]], point[corners[k + 2]]});
  }

  // The scene's node trees, depth first in the order recursion would take, on a stack of its own
  // (a rig's joint chain may be thousands of nodes deep).
  void nodes(const std::vector<int>& roots) {
    visited.assign(model.nodes.size(), 0);
    std::vector<std::pair<int, Eigen::Affine3d>> stack;
    for (auto r = roots.rbegin(); r != roots.rend(); ++r) stack.emplace_back(*r, Eigen::Affine3d::Identity());
    while (!stack.empty()) {
      const auto [index, parent] = stack.back();
      stack.pop_back();
      if (index < 0 || index >= int(model.nodes.size())) throw InputError("glTF " + path + ": node " + std::to_string(index) + " does not exist");
      if (visited[index]++)
        throw InputError("glTF " + path + ": node " + std::to_string(index) + " is reached twice (glTF nodes form a tree: one parent each)");
      const tinygltf::Node& n = model.nodes[index];
      const Eigen::Affine3d t = parent * node_transform(n);
      if (n.mesh >= 0) {
        if (n.mesh >= int(model.meshes.size())) throw InputError("glTF " + path + ": node " + std::to_string(index) + " names a missing mesh");
        for (const auto& p : model.meshes[n.mesh].primitives) primitive(p, t, index);
      }
      for (auto c = n.children.rbegin(); c != n.children.rend(); ++c) stack.emplace_back(*c, t);
    }
  }
};

// tinygltf hands an image in a buffer view to its decoder with the view's length unchecked against
// the buffer (a fuzzed .glb made stb read past the file's bytes), and decodes whatever format stb
// recognises. So images are not decoded while loading: a buffer-view image is left for
// encoded_image, which checks its view; an image from a URI (data or file, whose bytes tinygltf
// read itself) is kept encoded in image->image, width 0 marking it as such.
bool keep_encoded_image(tinygltf::Image* image, const int, std::string*, std::string*, int, int, const unsigned char* bytes, int size,
                        void*) {
  if (image->bufferView == -1 && bytes && size > 0) image->image.assign(bytes, bytes + size);
  image->width = image->height = image->component = image->bits = 0;
  return true;
}

// The encoded bytes of an image (its checked buffer view, or what keep_encoded_image kept).
std::pair<const unsigned char*, size_t> encoded_image(const tinygltf::Model& m, const tinygltf::Image& im) {
  if (im.bufferView == -1) return {im.image.data(), im.image.size()};
  if (im.bufferView < 0 || im.bufferView >= int(m.bufferViews.size())) return {nullptr, 0};
  const tinygltf::BufferView& v = m.bufferViews[im.bufferView];
  if (v.buffer < 0 || v.buffer >= int(m.buffers.size())) return {nullptr, 0};
  const std::vector<unsigned char>& data = m.buffers[v.buffer].data;
  if (v.byteOffset > data.size() || v.byteLength > data.size() - v.byteOffset) return {nullptr, 0};
  return {data.data() + v.byteOffset, v.byteLength};
}

// Decodes a PNG or JPEG (the two formats glTF allows; stb's other decoders are not offered
// fuzzed bytes) to RGBA, after its own header: at most kMaxImageSide a side, and no more pixels
// than its bytes can hold: 8 bytes a pixel (16-bit RGBA, what stb may decode into) at most 1100
// times the file (deflate's ratio is at most 1032:1; a fuzzed 128 KB file claiming more made stb
// allocate 1-2 GB). Throws InputError naming the problem.
Image decode_texture(const unsigned char* bytes, size_t size, const std::string& what) {
  const bool png = size >= 8 && std::memcmp(bytes, "\x89PNG\r\n\x1a\n", 8) == 0;
  const bool jpeg = size >= 3 && bytes[0] == 0xFF && bytes[1] == 0xD8 && bytes[2] == 0xFF;
  if (!png && !jpeg) throw InputError(what + ": its texture is neither PNG nor JPEG");
  // stb sizes its buffer by a PNG chunk's stated length before reading it (a 2.4 KB image said
  // 2 GB): every chunk must fit in the bytes, up to IEND.
  for (size_t at = 8; png;) {
    if (size - at < 12) throw InputError(what + ": its PNG texture is cut short (no IEND chunk)");
    const size_t length = size_t(bytes[at]) << 24 | size_t(bytes[at + 1]) << 16 | size_t(bytes[at + 2]) << 8 | bytes[at + 3];
    if (length > size - at - 12) throw InputError(what + ": a chunk of its PNG texture runs past the texture's bytes");
    if (std::memcmp(bytes + at + 4, "IEND", 4) == 0) break;
    at += 12 + length;
  }
  int w = 0, h = 0, c = 0;
  if (size > size_t(INT_MAX) || !stbi_info_from_memory(bytes, int(size), &w, &h, &c))
    throw InputError(what + ": its texture's header cannot be read");
  if (w < 1 || h < 1 || w > kMaxImageSide || h > kMaxImageSide || 8.0 * w * h > 1100.0 * double(size) + (1 << 20))
    throw InputError(what + ": its texture claims " + std::to_string(w) + " x " + std::to_string(h) + " pixels in " +
                     std::to_string(size) + " bytes (at most " + std::to_string(kMaxImageSide) + " a side, and what the bytes can hold)");
  unsigned char* p = stbi_load_from_memory(bytes, int(size), &w, &h, &c, 4);
  if (!p) throw InputError(what + ": its texture cannot be decoded (" + std::string(stbi_failure_reason() ? stbi_failure_reason() : "?") + ")");
  Image out(w, h, 4);
  std::memcpy(out.pixels.data(), p, out.pixels.size());
  stbi_image_free(p);
  return out;
}

// The base colour texture of material m as RGBA, or an empty image when it has none.
Image base_color_texture(const tinygltf::Model& model, int m, const std::string& what) {
  if (m < 0 || m >= int(model.materials.size())) return {};
  const int t = model.materials[m].pbrMetallicRoughness.baseColorTexture.index;
  if (t < 0 || t >= int(model.textures.size())) return {};
  const int s = model.textures[t].source;
  if (s < 0 || s >= int(model.images.size())) return {};
  const auto [bytes, size] = encoded_image(model, model.images[s]);
  if (!bytes || size == 0) throw InputError(what + ": its texture's bytes lie outside its buffer or are missing");
  return decode_texture(bytes, size, what);
}

}  // namespace

namespace gltf_internal {

namespace {

// tinygltf's own file functions open with fopen: a buffer or image URI naming a named pipe made
// the load wait for ever, and one naming a folder sized its buffer by the folder's seek offset
// (std::bad_alloc). Every file it reads comes through read_input_file instead, and a URI names a
// file when something is there, so that the reason it is not read reaches the message: the first
// refusal is kept in `refused` (tinygltf only warns about an image it could not read).
bool uri_exists(const std::string& path, void*) {
  std::error_code ec;
  return std::filesystem::exists(path, ec);
}

bool read_whole(std::vector<unsigned char>* out, std::string* err, const std::string& path, void* refused) {
  try {
    const std::string bytes = read_input_file(path, "file", kMaxMeshFileBytes);
    out->assign(bytes.begin(), bytes.end());
    return true;
  } catch (const InputError& e) {
    if (err) *err = e.what();
    std::string& first = *static_cast<std::string*>(refused);
    if (first.empty()) first = e.what();
    return false;
  }
}

}  // namespace

tinygltf::Model load_model(const std::string& path) {
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  loader.SetImageLoader(keep_encoded_image, nullptr);
  std::string refused;
  loader.SetFsCallbacks({uri_exists, tinygltf::ExpandFilePath, read_whole, tinygltf::WriteWholeFile, &refused});
  std::string err, warn;
  const bool ok = lower_extension(path) == ".glb" ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                                            : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  if (!refused.empty()) throw InputError("glTF " + path + ": " + refused);
  if (!ok) throw InputError("cannot read glTF " + path + ": " + (err.empty() ? "the file could not be parsed" : err));
  return model;
}

GltfScene read_model(const tinygltf::Model& model, const std::string& path, const VerticesRead& on_vertices) {
  Reader r{model, path, {}, {}, {}, true, -1, {}, {}, false, on_vertices};
  if (!model.scenes.empty()) {
    const int s = model.defaultScene >= 0 && model.defaultScene < int(model.scenes.size()) ? model.defaultScene : 0;
    r.nodes(model.scenes[s].nodes);
  } else {
    for (const auto& mesh : model.meshes)
      for (const auto& p : mesh.primitives) r.primitive(p, Eigen::Affine3d::Identity(), -1);
  }
  if (r.out.soup.triangles.empty()) throw InputError("glTF " + path + " has no triangles");
  if (r.any_color) r.out.soup.colors = std::move(r.colors);
  if (r.all_uv) {
    r.out.soup.uv = std::move(r.uv);
    r.out.texture = base_color_texture(model, r.textured_material, "glTF " + path);
  }
  return std::move(r.out);
}

}  // namespace gltf_internal

GltfScene read_gltf(const std::string& path) { return gltf_internal::read_model(gltf_internal::load_model(path), path); }

namespace gltf_internal {

int add_view(tinygltf::Model& m, const void* bytes, size_t size, int target) {
  std::vector<unsigned char>& data = m.buffers[0].data;
  while (data.size() % 4) data.push_back(0);
  tinygltf::BufferView v;
  v.buffer = 0;
  v.byteOffset = data.size();
  v.byteLength = size;
  v.target = target;
  const auto* p = static_cast<const unsigned char*>(bytes);
  data.insert(data.end(), p, p + size);
  m.bufferViews.push_back(v);
  return int(m.bufferViews.size()) - 1;
}

int add_accessor(tinygltf::Model& m, int view, int component, int type, size_t count, std::vector<double> lo, std::vector<double> hi) {
  tinygltf::Accessor a;
  a.bufferView = view;
  a.componentType = component;
  a.type = type;
  a.count = count;
  a.minValues = std::move(lo);
  a.maxValues = std::move(hi);
  m.accessors.push_back(a);
  return int(m.accessors.size()) - 1;
}

}  // namespace gltf_internal
namespace {

using gltf_internal::add_accessor;
using gltf_internal::add_view;

// One glTF vertex per (mesh vertex, uv) pair: positions, normals, uv and the triangle indices.
struct SplitVertices {
  std::vector<float> position, normal, uv;
  std::vector<uint32_t> index;
  std::vector<int> source;  // per glTF vertex, its mesh vertex
};

SplitVertices split_vertices(const Mesh& mesh) {
  Mesh m = mesh;
  m.request_face_normals();
  m.request_vertex_normals();
  m.update_normals();
  const bool has_uv = m.has_halfedge_texcoords2D();
  SplitVertices s;
  std::map<std::tuple<int, double, double>, uint32_t> id;
  for (auto f : m.faces())
    for (auto h : m.fh_range(f)) {
      const auto v = m.to_vertex_handle(h);
      const double u = has_uv ? m.texcoord2D(h)[0] : 0, w = has_uv ? 1.0 - m.texcoord2D(h)[1] : 0;
      const auto [it, added] = id.emplace(std::make_tuple(v.idx(), u, w), uint32_t(s.position.size() / 3));
      if (added) {
        for (int c = 0; c < 3; ++c) s.position.push_back(float(m.point(v)[c]));
        for (int c = 0; c < 3; ++c) s.normal.push_back(float(m.normal(v)[c]));
        if (has_uv) s.uv.insert(s.uv.end(), {float(u), float(w)});
        s.source.push_back(v.idx());
      }
      s.index.push_back(it->second);
    }
  return s;
}

void add_texture(tinygltf::Model& m, const std::string& png, tinygltf::Primitive& p) {
  // read_text_file: the texture may be this command's own output, still under its temporary name
  // until the command's OutputCommit renames it (transfer -o OUT.glb embeds the atlas it wrote).
  const std::string bytes = read_text_file(png);
  if (bytes.size() < 8 || bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0) throw InputError("texture " + png + " is not a PNG file");
  tinygltf::Image image;
  image.bufferView = add_view(m, bytes.data(), bytes.size(), 0);
  image.mimeType = "image/png";
  image.name = fs::path(png).stem().string();
  m.images.push_back(image);
  tinygltf::Sampler sampler;
  sampler.magFilter = TINYGLTF_TEXTURE_FILTER_LINEAR;
  sampler.minFilter = TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR;
  m.samplers.push_back(sampler);
  tinygltf::Texture t;
  t.source = 0;
  t.sampler = 0;
  m.textures.push_back(t);
  tinygltf::Material mat;
  mat.name = "sdm_texture";
  mat.pbrMetallicRoughness.baseColorTexture.index = 0;
  mat.pbrMetallicRoughness.metallicFactor = 0;
  mat.pbrMetallicRoughness.roughnessFactor = 1;
  m.materials.push_back(mat);
  p.material = 0;
}

}  // namespace

namespace gltf_internal {

MeshModel mesh_model(const Mesh& mesh, const std::string& path, const std::string& texture_png) {
  const std::string ext = lower_extension(path);
  if (ext != ".glb" && ext != ".gltf") throw InputError("cannot write glTF " + path + ": name a .glb or .gltf file");
  SplitVertices s = split_vertices(mesh);
  MeshModel out;
  tinygltf::Model& m = out.model;
  m.asset.version = "2.0";
  m.asset.generator = "sdm";
  m.buffers.resize(1);
  std::vector<double> lo(3, INFINITY), hi(3, -INFINITY);
  for (size_t i = 0; i < s.position.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], double(s.position[i]));
    hi[i % 3] = std::max(hi[i % 3], double(s.position[i]));
  }
  const size_t n = s.position.size() / 3;
  tinygltf::Primitive p;
  p.mode = TINYGLTF_MODE_TRIANGLES;
  p.attributes["POSITION"] = add_accessor(m, add_view(m, s.position.data(), 4 * s.position.size(), TINYGLTF_TARGET_ARRAY_BUFFER),
                                          TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n, lo, hi);
  p.attributes["NORMAL"] = add_accessor(m, add_view(m, s.normal.data(), 4 * s.normal.size(), TINYGLTF_TARGET_ARRAY_BUFFER),
                                        TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n);
  if (!s.uv.empty())
    p.attributes["TEXCOORD_0"] = add_accessor(m, add_view(m, s.uv.data(), 4 * s.uv.size(), TINYGLTF_TARGET_ARRAY_BUFFER),
                                              TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, n);
  p.indices = add_accessor(m, add_view(m, s.index.data(), 4 * s.index.size(), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                           TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, s.index.size());
  if (!s.uv.empty() && !texture_png.empty()) add_texture(m, texture_png, p);
  tinygltf::Mesh gm;
  gm.name = fs::path(path).stem().string();
  gm.primitives.push_back(p);
  m.meshes.push_back(gm);
  tinygltf::Node node;
  node.mesh = 0;
  m.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  m.scenes.push_back(scene);
  m.defaultScene = 0;
  out.source_vertex = std::move(s.source);
  return out;
}

void save_model(tinygltf::Model& m, const std::string& path) {
  m.buffers[0].data.resize((m.buffers[0].data.size() + 3) / 4 * 4, 0);
  std::ostringstream bytes;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToStream(&m, bytes, false, lower_extension(path) == ".glb"))
    throw std::runtime_error("cannot write glTF " + path + ": tinygltf refused the model");
  const std::string data = bytes.str();
  write_atomically(path, [&](const std::string& tmp) { write_bytes_checked(tmp, data.data(), data.size(), path); });
}

}  // namespace gltf_internal

void write_gltf(const Mesh& mesh, const std::string& path, const std::string& texture_png) {
  gltf_internal::MeshModel m = gltf_internal::mesh_model(mesh, path, texture_png);
  gltf_internal::save_model(m.model, path);
}

}  // namespace sdm
