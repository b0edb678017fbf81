// sdm_py: the skeleton, the layout (STM uv), skeleton displacement maps and texture transfer of sdm
// for Python, on numpy arrays (pybind11). Vertices are float64 (n, 3), faces int (m, 3); every
// function validates its mesh as the command line does (closed, manifold, no NaN) and raises
// ValueError with the same message where the command would exit 2.
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/encode_sdm.h"
#include "libsdm/map/sdm_exr.h"
#include "libsdm/pose/pose_skeleton.h"
#include "libstm/core/errors.h"
#include "libstm/core/version.h"
#include "libstm/layout/compute_layout.h"
#include "libstm/layout/layout_json.h"
#include "libstm/layout/stm_coordinates.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh.h"
#include "libstm/render/gl_context.h"
#include "libstm/skeleton/extract_skeleton.h"
#include "libstm/transfer/carry_attributes.h"
#include "libstm/transfer/transfer_texture.h"

#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

namespace py = pybind11;
using RowMatrix3d = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using RowMatrix3i = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;
using RowMatrix2d = Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>;

namespace {

// (m, 3, 2) corner uv (or (3m, 2)) flattened to one row per corner.
Eigen::MatrixX2d corner_uv(const std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>>& uv) {
  if (!uv) return {};
  const auto& a = *uv;
  if (!((a.ndim() == 3 && a.shape(1) == 3 && a.shape(2) == 2) || (a.ndim() == 2 && a.shape(1) == 2)))
    throw sdm::InputError("uv must have the shape (faces, 3, 2) or (3 * faces, 2)");
  const Eigen::Index rows = a.ndim() == 3 ? a.shape(0) * 3 : a.shape(0);
  return Eigen::Map<const RowMatrix2d>(a.data(), rows, 2);
}

sdm::Mesh mesh_of(const RowMatrix3d& V, const RowMatrix3i& F, const Eigen::MatrixX2d& uv, const std::string& what) {
  return sdm::mesh_from_arrays(V, F, uv, what);
}

// Per face corner (in the faces' order of the mesh), the halfedge texcoords: (m, 3, 2).
py::array_t<double> uv_array(const sdm::Mesh& mesh) {
  py::array_t<double> uv({py::ssize_t(mesh.n_faces()), py::ssize_t(3), py::ssize_t(2)});
  auto u = uv.mutable_unchecked<3>();
  for (auto f : mesh.faces()) {
    int c = 0;
    for (auto h : mesh.fh_range(f)) {
      const auto& t = mesh.texcoord2D(h);
      u(f.idx(), c, 0) = t[0];
      u(f.idx(), c, 1) = t[1];
      ++c;
    }
  }
  return uv;
}

py::dict skeleton_dict(const sdm::Skeleton& s) {
  RowMatrix3d nodes(s.nodes.size(), 3);
  for (size_t i = 0; i < s.nodes.size(); ++i) nodes.row(i) = s.nodes[i].transpose();
  Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor> edges(s.edges.size(), 2);
  for (size_t i = 0; i < s.edges.size(); ++i) edges.row(i) << s.edges[i][0], s.edges[i][1];
  py::dict d;
  d["nodes"] = nodes;
  d["edges"] = edges;
  d["vertex_node"] = Eigen::VectorXi(Eigen::Map<const Eigen::VectorXi>(s.vertex_node.data(), s.vertex_node.size()));
  d["cycles"] = s.cycles();
  d["ends"] = s.end_nodes();
  d["branch_nodes"] = s.branch_nodes();
  return d;
}

sdm::Skeleton skeleton_from_dict(const py::dict& d) {
  sdm::Skeleton s;
  const RowMatrix3d nodes = d["nodes"].cast<RowMatrix3d>();
  const auto edges = d["edges"].cast<Eigen::Matrix<int, Eigen::Dynamic, 2, Eigen::RowMajor>>();
  const Eigen::VectorXi vn = d["vertex_node"].cast<Eigen::VectorXi>();
  for (Eigen::Index i = 0; i < nodes.rows(); ++i) s.nodes.push_back(nodes.row(i).transpose());
  for (Eigen::Index i = 0; i < edges.rows(); ++i) s.edges.push_back({edges(i, 0), edges(i, 1)});
  s.vertex_node.assign(vn.data(), vn.data() + vn.size());
  sdm::check_skeleton_geometry(s);
  return s;
}

sdm::GlContext& gl() {
  static std::unique_ptr<sdm::GlContext> context;
  if (!context) context = std::make_unique<sdm::GlContext>();
  return *context;
}

py::tuple mesh_arrays(const sdm::Mesh& m) {
  return py::make_tuple(RowMatrix3d(sdm::vertex_matrix(m)), RowMatrix3i(sdm::face_matrix(m)));
}

py::dict skeleton(const RowMatrix3d& V, const RowMatrix3i& F) {
  const sdm::Mesh mesh = mesh_of(V, F, {}, "(V, F)");
  sdm::Skeleton s;
  {
    py::gil_scoped_release release;  // other Python threads run meanwhile
    s = sdm::extract_skeleton(mesh);
  }
  return skeleton_dict(s);
}

py::dict layout(const RowMatrix3d& V, const RowMatrix3i& F, int size, int margin, const std::optional<py::dict>& skel) {
  const sdm::Mesh mesh = mesh_of(V, F, {}, "(V, F)");
  sdm::LayoutOptions options;
  options.size = size;
  options.margin = margin;
  const sdm::Skeleton s = skel ? skeleton_from_dict(*skel) : sdm::extract_skeleton(mesh);
  const sdm::Layout l = sdm::compute_layout(mesh, s, options);
  const sdm::StmCoordinates stm = sdm::stm_coordinates(mesh, l);
  py::dict d;
  d["uv"] = uv_array(stm.mesh);
  d["faces"] = RowMatrix3i(sdm::face_matrix(stm.mesh));
  d["face_segment"] = Eigen::VectorXi(Eigen::Map<const Eigen::VectorXi>(stm.face_segment.data(), stm.face_segment.size()));
  d["stretch"] = stm.stretch;
  d["coverage"] = stm.coverage;
  d["segments"] = l.segments.size();
  d["skeleton"] = skeleton_dict(l.skeleton);
  d["json"] = sdm::layout_to_json(l).dump();
  return d;
}

py::dict encode(const RowMatrix3d& V, const RowMatrix3i& F, const std::string& path, int size, const std::string& precision) {
  const sdm::Mesh mesh = mesh_of(V, F, {}, "(V, F)");
  sdm::LayoutOptions options;
  options.size = size;
  const sdm::Layout l = sdm::compute_layout(mesh, sdm::extract_skeleton(mesh), options);
  sdm::EncodeStats st;
  const sdm::SdmImage im = sdm::encode_sdm(mesh, l, {}, &st);
  sdm::write_sdm_exr(im, path, sdm::SdmPrecision::parse(precision));
  py::dict d;
  d["path"] = path;
  d["size"] = im.width;
  d["segments"] = l.segments.size();
  d["texels"] = st.texels;
  d["own_hits"] = st.own_hits;
  d["other_hits"] = st.other_hits;
  d["filled"] = st.filled;
  d["base_faces"] = st.base_faces;
  return d;
}

// decode_sdm with the GIL released: other Python threads run meanwhile.
sdm::Mesh decode_without_gil(const sdm::SdmImage& im, const sdm::DecodeOptions& o) {
  py::gil_scoped_release release;
  return sdm::decode_sdm(im, o);
}

py::tuple decode(const std::string& path, int level, const std::map<int, int>& segment_levels) {
  const sdm::SdmImage im = sdm::read_sdm_exr(path);
  sdm::DecodeOptions o;
  o.level = level;
  o.segment_level = segment_levels;
  return mesh_arrays(decode_without_gil(im, o));
}

// The map's own skeleton (the rest pose that `pose` moves): nodes, edges, and per edge its segment id
// (segments are the skeleton's edges, the ids of --lod-segment and segment_levels), and the root of
// its bone tree (pose_skeleton's).
py::dict map_skeleton(const std::string& path) {
  const sdm::Skeleton s = sdm::layout_from_json(sdm::read_sdm_exr(path).layout).skeleton;
  py::dict d = skeleton_dict(s);
  d.attr("pop")("vertex_node");  // the encoded mesh's vertices, not the decode's
  d["root"] = sdm::skeleton_root(s);
  return d;
}

// `posed` set from the dict of `pose` (nodes, optionally node_rotations and segment_radius_scale).
void apply_pose_dict(const py::dict& d, sdm::PosedSkeleton& posed) {
  const RowMatrix3d nodes = d["nodes"].cast<RowMatrix3d>();
  if (size_t(nodes.rows()) != posed.nodes.size())
    throw sdm::InputError("skeleton['nodes'] has " + std::to_string(nodes.rows()) + " rows but the map's skeleton has " +
                          std::to_string(posed.nodes.size()) + " nodes (see map_skeleton)");
  for (Eigen::Index i = 0; i < nodes.rows(); ++i) posed.nodes[size_t(i)] = nodes.row(i).transpose();
  if (d.contains("node_rotations") && !d["node_rotations"].is_none()) {
    const auto q = d["node_rotations"].cast<Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>>();
    if (size_t(q.rows()) != posed.nodes.size())
      throw sdm::InputError("skeleton['node_rotations'] needs one row [x, y, z, w] per node (NaN rows: derived)");
    posed.node_rotations.assign(posed.nodes.size(), std::nullopt);
    for (Eigen::Index i = 0; i < q.rows(); ++i)
      if (q.row(i).allFinite()) posed.node_rotations[size_t(i)] = Eigen::Quaterniond(q(i, 3), q(i, 0), q(i, 1), q(i, 2)).normalized();
  }
  if (d.contains("segment_radius_scale") && !d["segment_radius_scale"].is_none())
    posed.segment_radius_scale = d["segment_radius_scale"].cast<std::vector<double>>();
}

// Decodes the map at `level` posed through its skeleton, as 'sdm pose' and 'sdm decode --skeleton'.
py::tuple pose(const std::string& path, int level, const std::optional<py::dict>& skeleton,
               const std::vector<std::tuple<int, Eigen::Vector3d, double>>& rotate, const std::map<int, double>& scale_radius,
               const std::map<int, int>& segment_levels) {
  const sdm::SdmImage im = sdm::read_sdm_exr(path);
  const sdm::Skeleton rest = sdm::layout_from_json(im.layout).skeleton;
  sdm::PosedSkeleton posed = rest;
  if (skeleton) apply_pose_dict(*skeleton, posed);
  for (const auto& [node, axis, degrees] : rotate) {
    if (!(axis.norm() > 0) || !axis.allFinite() || !std::isfinite(degrees))
      throw sdm::InputError("rotate (" + std::to_string(node) + ", axis, degrees): the axis needs a direction and the angle a finite value");
    sdm::rotate_subtree(rest, posed, node, Eigen::Quaterniond(Eigen::AngleAxisd(degrees * M_PI / 180, axis.normalized())));
  }
  for (const auto& [segment, factor] : scale_radius) {
    if (segment < 0 || size_t(segment) >= posed.edges.size() || !(factor > 0) || !std::isfinite(factor))
      throw sdm::InputError("scale_radius {" + std::to_string(segment) + ": factor}: the segment must be one of the map's " +
                            std::to_string(posed.edges.size()) + " and the factor > 0");
    if (posed.segment_radius_scale.empty()) posed.segment_radius_scale.assign(posed.edges.size(), 1.0);
    posed.segment_radius_scale[size_t(segment)] *= factor;
  }
  sdm::pose_skeleton(rest, posed);  // the graph and the pose fields checked before the work
  sdm::DecodeOptions o;
  o.level = level;
  o.segment_level = segment_levels;
  o.skeleton = std::move(posed);
  return mesh_arrays(decode_without_gil(im, o));
}

py::dict transfer(const RowMatrix3d& Vs, const RowMatrix3i& Fs, const RowMatrix3d& Vt, const RowMatrix3i& Ft,
                  const std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>>& uv,
                  const std::optional<py::array_t<uint8_t, py::array::c_style | py::array::forcecast>>& texture, int size,
                  bool force) {
  if (bool(uv) != bool(texture)) throw sdm::InputError("give uv and texture together, or neither (the correspondence alone)");
  sdm::Mesh source = mesh_of(Vs, Fs, corner_uv(uv), "(source_V, source_F)");
  const sdm::Mesh target = mesh_of(Vt, Ft, {}, "(target_V, target_F)");
  sdm::SkeletonStats stats_a, stats_b;
  const sdm::Skeleton a = sdm::extract_skeleton(source, sdm::transfer_skeleton_options(), nullptr, &stats_a);
  const sdm::Skeleton b = sdm::extract_skeleton(target, sdm::transfer_skeleton_options(), nullptr, &stats_b);
  sdm::Image image;
  if (texture) {
    const auto& t = *texture;
    if (t.ndim() != 3 || (t.shape(2) != 3 && t.shape(2) != 4)) throw sdm::InputError("texture must have the shape (height, width, 3 or 4)");
    image = sdm::Image(int(t.shape(1)), int(t.shape(0)), 4, 255);
    for (py::ssize_t y = 0; y < t.shape(0); ++y)
      for (py::ssize_t x = 0; x < t.shape(1); ++x)
        for (py::ssize_t c = 0; c < t.shape(2); ++c) image.at(int(x), int(y))[c] = t.at(y, x, c);
  } else {  // a grey source texture: only the correspondence is wanted
    sdm::TexturedMesh g = sdm::texture_from_vertex_colors(gl(), source, std::vector<Eigen::Vector3f>(source.n_vertices(), Eigen::Vector3f::Constant(0.5f)), a, size, 8);
    source = std::move(g.mesh);
    image = std::move(g.texture);
  }
  sdm::TransferOptions o;
  o.size = size;
  o.force = force;
  o.other_candidate = [&](bool is_target) -> std::optional<sdm::Skeleton> {
    return sdm::other_transfer_candidate(is_target ? target : source, is_target ? stats_b : stats_a);
  };
  const sdm::TextureTransfer r = sdm::transfer_texture(gl(), source, image, a, target, b, o);
  py::dict d;
  Eigen::VectorXi face(r.correspondence.size());
  RowMatrix3d bary(r.correspondence.size(), 3);
  for (size_t i = 0; i < r.correspondence.size(); ++i) {
    face(i) = r.correspondence[i].face;
    bary.row(i) = r.correspondence[i].barycentric.transpose();
  }
  d["face"] = face;
  d["barycentric"] = bary;
  d["uv"] = uv_array(r.target);
  d["faces"] = RowMatrix3i(sdm::face_matrix(r.target));
  py::array_t<uint8_t> atlas({py::ssize_t(r.atlas.height), py::ssize_t(r.atlas.width), py::ssize_t(4)});
  std::copy(r.atlas.pixels.begin(), r.atlas.pixels.end(), atlas.mutable_data());
  d["atlas"] = atlas;
  d["fit_rms"] = r.fit_rms;
  d["fit_p99"] = r.fit_p99;
  d["registered"] = r.kind == sdm::CorrespondenceKind::registered;
  return d;
}

// The dense correspondence alone (correspond, without GL): per target vertex its source point.
py::dict correspondence(const RowMatrix3d& Vs, const RowMatrix3i& Fs, const RowMatrix3d& Vt, const RowMatrix3i& Ft, bool force) {
  const sdm::Mesh source = mesh_of(Vs, Fs, {}, "(source_V, source_F)");
  const sdm::Mesh target = mesh_of(Vt, Ft, {}, "(target_V, target_F)");
  sdm::SkeletonStats stats_a, stats_b;
  const sdm::Skeleton a = sdm::extract_skeleton(source, sdm::transfer_skeleton_options(), nullptr, &stats_a);
  const sdm::Skeleton b = sdm::extract_skeleton(target, sdm::transfer_skeleton_options(), nullptr, &stats_b);
  sdm::CorrespondOptions o;
  o.force = force;
  o.other_candidate = [&](bool is_target) -> std::optional<sdm::Skeleton> {
    return sdm::other_transfer_candidate(is_target ? target : source, is_target ? stats_b : stats_a);
  };
  const sdm::Correspondence c = sdm::correspond(source, a, target, b, o);
  if (c.points.empty()) throw sdm::InputError("the target was matched by its skeleton alone (the genera differ): no point correspondence");
  py::dict d;
  Eigen::VectorXi face(c.points.size());
  RowMatrix3d bary(c.points.size(), 3);
  for (size_t i = 0; i < c.points.size(); ++i) face(i) = c.points[i].face, bary.row(i) = c.points[i].barycentric.transpose();
  d["face"] = face;
  d["barycentric"] = bary;
  d["kind"] = sdm::kind_name(c.kind);
  d["fit_rms"] = c.diagnostics.fit_rms;
  d["fit_p99"] = c.diagnostics.fit_p99;
  d["refined"] = c.diagnostics.refined;
  return d;
}

}  // namespace

PYBIND11_MODULE(sdm_py, m) {
  m.doc() = "sdm: skeleton texture maps and skeleton displacement maps on numpy arrays";
  m.attr("__version__") = SDM_VERSION;
  py::register_exception<sdm::InputError>(m, "InputError", PyExc_ValueError);
  m.def("read_mesh", [](const std::string& path) { return mesh_arrays(sdm::load_mesh(path).mesh); }, py::arg("path"),
        "Reads and validates a mesh file (.obj, .off, .ply, .stl): returns (V, F).");
  m.def("write_mesh", [](const std::string& path, const RowMatrix3d& V, const RowMatrix3i& F) {
          sdm::write_mesh(mesh_of(V, F, {}, "(V, F)"), path); }, py::arg("path"), py::arg("V"), py::arg("F"),
        "Writes a mesh file, the format chosen by the extension.");
  m.def("skeleton", &skeleton, py::arg("V"), py::arg("F"),
        "Curve skeleton of a closed mesh: dict with nodes (k, 3), edges (e, 2), vertex_node (n,), cycles, ends, branch_nodes.");
  m.def("layout", &layout, py::arg("V"), py::arg("F"), py::arg("size") = 1024, py::arg("margin") = 4, py::arg("skeleton") = py::none(),
        "Skeleton texture map: dict with uv (m, 3, 2) per corner of faces (m, 3), face_segment, stretch, coverage, "
        "segments, skeleton and the layout as JSON text.");
  m.def("encode", &encode, py::arg("V"), py::arg("F"), py::arg("path"), py::arg("size") = 1024, py::arg("precision") = "10",
        "Encodes the mesh as a skeleton displacement map (OpenEXR) at path; returns its statistics.");
  m.def("decode", &decode, py::arg("path"), py::arg("level") = 3, py::arg("segment_levels") = std::map<int, int>{},
        "Rebuilds the surface from a skeleton displacement map at a level of detail: returns (V, F). segment_levels "
        "{segment: level} sets some segments' own level, as 'sdm decode --lod-segment'.");
  m.def("map_skeleton", &map_skeleton, py::arg("path"),
        "The skeleton a map was encoded on, its rest pose: dict with nodes (k, 3), edges (e, 2) (edge i is segment i), "
        "cycles, ends, branch_nodes, root (the node its bone tree hangs from).");
  m.def("pose", &pose, py::arg("path"), py::arg("level") = 3, py::arg("skeleton") = py::none(),
        py::arg("rotate") = std::vector<std::tuple<int, Eigen::Vector3d, double>>{}, py::arg("scale_radius") = std::map<int, double>{},
        py::arg("segment_levels") = std::map<int, int>{},
        "Decodes a map posed through its skeleton, as 'sdm pose': returns (V, F). skeleton: dict with the posed nodes "
        "(k, 3) of map_skeleton's graph, optionally node_rotations (k, 4) [x, y, z, w] (NaN rows: derived) and "
        "segment_radius_scale (e,); rotate: [(node, axis (3,), degrees)], each turning the part below node about it "
        "(applied in order after skeleton); scale_radius: {segment: factor}; segment_levels as decode's.");
  m.def("transfer", &transfer, py::arg("source_V"), py::arg("source_F"), py::arg("target_V"), py::arg("target_F"),
        py::arg("uv") = py::none(), py::arg("texture") = py::none(), py::arg("size") = 1024, py::arg("force") = false,
        "Texture transfer between models with the same skeleton branching: dict with face (n,) and barycentric "
        "(n, 3), the source point of every target vertex; uv (m, 3, 2) per corner of faces (m, 3) of the target "
        "into atlas (h, w, 4); fit_rms, fit_p99 (fractions of the diagonal). uv (per source face corner) and "
        "texture (h, w, 3 or 4, uint8) are optional.");
  m.def("correspondence", &correspondence, py::arg("source_V"), py::arg("source_F"), py::arg("target_V"), py::arg("target_F"),
        py::arg("force") = false,
        "The dense correspondence of transfer without a texture or GL: dict with face (n,) and barycentric (n, 3), the "
        "source point of every target vertex; kind ('carried', 'bent' or 'registered'), fit_rms, fit_p99, refined.");
}
