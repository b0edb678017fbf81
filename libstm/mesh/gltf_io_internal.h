#pragma once
/// What gltf_io.cpp shares with the other glTF readers and writers of this folder (gltf_skin.cpp):
/// tinygltf models loaded and read into a scene, and a mesh's model built and saved, so that a
/// writer adding to the model (a skin) reuses write_gltf's code paths. Needs tinygltf's header
/// (Debian's libtinygltf-dev, a private dependency of sdm_core): not for code outside libstm/mesh.
#include "libstm/core/errors.h"
#include "libstm/mesh/gltf_io.h"
#include "libstm/mesh/mesh.h"

#include <tiny_gltf.h>

#include <Eigen/Geometry>

#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

namespace sdm::gltf_internal {

/// The bytes of element i of an accessor, after checking that the whole accessor lies inside its
/// buffer view and the view inside its buffer (tinygltf does not check every combination).
class AccessorView {
 public:
  AccessorView(const tinygltf::Model& m, int index, const std::string& what) : what_(what) {
    if (index < 0 || index >= int(m.accessors.size())) throw InputError(what + ": accessor " + std::to_string(index) + " does not exist");
    const tinygltf::Accessor& a = m.accessors[index];
    count_ = a.count;
    components_ = tinygltf::GetNumComponentsInType(a.type);
    component_size_ = tinygltf::GetComponentSizeInBytes(a.componentType);
    type_ = a.componentType;
    normalized_ = a.normalized;
    if (components_ <= 0 || component_size_ <= 0) throw InputError(what + ": accessor " + std::to_string(index) + " has an unknown type");
    if (a.sparse.isSparse) throw InputError(what + ": sparse accessors are not supported");
    if (a.bufferView < 0 || a.bufferView >= int(m.bufferViews.size()))
      throw InputError(what + ": accessor " + std::to_string(index) + " has no buffer view");
    const tinygltf::BufferView& v = m.bufferViews[a.bufferView];
    if (v.buffer < 0 || v.buffer >= int(m.buffers.size())) throw InputError(what + ": buffer view " + std::to_string(a.bufferView) + " has no buffer");
    const std::vector<unsigned char>& data = m.buffers[v.buffer].data;
    const size_t element = size_t(components_) * component_size_;
    stride_ = v.byteStride ? v.byteStride : element;
    const size_t need = count_ == 0 ? 0 : a.byteOffset + stride_ * (count_ - 1) + element;
    if (v.byteOffset > data.size() || v.byteLength > data.size() - v.byteOffset || need > v.byteLength || stride_ < element)
      throw InputError(what + ": accessor " + std::to_string(index) + " reaches outside its buffer (the file is truncated or corrupt)");
    base_ = data.data() + v.byteOffset + a.byteOffset;
  }
  size_t count() const { return count_; }
  int components() const { return components_; }
  /// Component c of element i as a double (normalized integers mapped to [0, 1]).
  double get(size_t i, int c) const {
    const unsigned char* p = base_ + i * stride_ + size_t(c) * component_size_;
    switch (type_) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, p, 4); return f; }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized_ ? *p / 255.0 : *p;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t s; std::memcpy(&s, p, 2); return normalized_ ? s / 65535.0 : s; }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t u; std::memcpy(&u, p, 4); return u; }
      default: throw InputError(what_ + ": unsupported component type " + std::to_string(type_));
    }
  }

 private:
  std::string what_;
  const unsigned char* base_ = nullptr;
  size_t count_ = 0, stride_ = 0;
  int components_ = 0, component_size_ = 0, type_ = 0;
  bool normalized_ = false;
};

/// A node's local transform (its matrix, or translation * rotation * scale).
Eigen::Affine3d node_transform(const tinygltf::Node& n);

/// Parses a .glb (by extension) or .gltf, images left encoded (read_model decodes the one it uses).
/// \throw InputError naming the file when it cannot be parsed.
tinygltf::Model load_model(const std::string& path);

/// Called for each triangle primitive read_model reads, after its vertices were welded: the node
/// holding it (-1 when the file has no scene and meshes are read bare), the primitive, and per
/// vertex of the primitive the index of the point it became.
using VerticesRead = std::function<void(int node, const tinygltf::Primitive& p, const std::vector<int>& point)>;

/// read_gltf on a loaded model (gltf_io.h has the contract); `path` names the file in messages.
GltfScene read_model(const tinygltf::Model& model, const std::string& path, const VerticesRead& on_vertices = {});

/// Appends `size` bytes to buffer 0, 4-byte aligned, as a new buffer view with `target` (0: none);
/// returns the view's index.
int add_view(tinygltf::Model& m, const void* bytes, size_t size, int target);

/// Adds an accessor of `count` elements on `view`; returns its index.
int add_accessor(tinygltf::Model& m, int view, int component, int type, size_t count, std::vector<double> lo = {},
                 std::vector<double> hi = {});

/// write_gltf's model before it is saved: one mesh (0) of one triangle primitive in node 0, the
/// default scene's only node, with one buffer (0).
struct MeshModel {
  tinygltf::Model model;
  std::vector<int> source_vertex;  ///< per glTF vertex (split at uv seams), the mesh vertex it came from
};

/// Builds write_gltf's model of `mesh` (`path` names the mesh; `texture_png` as write_gltf takes it).
/// \throw InputError for a path that is not .glb or .gltf, or a texture that is not a PNG file.
MeshModel mesh_model(const Mesh& mesh, const std::string& path, const std::string& texture_png);

/// Pads buffer 0 to 4 bytes and writes the model as .glb or .gltf (by extension), atomically.
/// \throw std::runtime_error when tinygltf refuses the model or the file cannot be written.
void save_model(tinygltf::Model& m, const std::string& path);

}  // namespace sdm::gltf_internal
