#include "libstm/mesh/mesh.h"

#include "libstm/core/atomic_file.h"
#include "libstm/core/errors.h"
#include "libstm/core/input_file.h"
#include "libstm/core/limits.h"
#include "libstm/mesh/add_faces.h"
#include "libstm/mesh/check_mesh_file.h"
#include "libstm/mesh/drop_small_parts.h"
#include "libstm/mesh/gltf_io.h"
#include "libstm/mesh/obj_material.h"
#include "libstm/mesh/point_cloud.h"
#include "libstm/mesh/read_binary_ply.h"
#include "libstm/mesh/read_plain_text.h"
#include "libstm/mesh/text_lines.h"
#include "libstm/mesh/triangulate_polygon.h"
#include "libstm/mesh/validate_mesh.h"
#include "libstm/mesh/write_positions.h"

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/Utils/Endian.hh>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <iomanip>
#include <map>
#include <sstream>

namespace fs = std::filesystem;

namespace sdm {
namespace {

using OpenMesh::Vec2f;
using OpenMesh::Vec3d;
using OpenMesh::Vec3f;
using OpenMesh::Vec3uc;
using OpenMesh::Vec4f;
using OpenMesh::Vec4uc;
using VH = OpenMesh::VertexHandle;
using FH = OpenMesh::FaceHandle;
using HH = OpenMesh::HalfedgeHandle;

// Receives what OpenMesh's readers parse, without building topology: polygons, corners' uv and
// material textures are kept as they are in the file so that validation sees the raw input.
class SoupImporter : public OpenMesh::IO::BaseImporter {
 public:
  std::vector<Eigen::Vector3d> points;
  std::vector<std::vector<int>> polygons;
  std::vector<std::vector<Eigen::Vector2d>> polygon_uv;  // per polygon corner, may be empty
  std::map<int, std::string> textures;
  std::map<int, int> texture_use;  // texture id -> faces using it
  std::vector<Eigen::Vector3f> colors;  // per point, RGB in [0, 1]; empty until the reader gives one

  VH add_vertex(const Vec3f& p) override { return add_vertex(Vec3d(p[0], p[1], p[2])); }
  VH add_vertex(const Vec3d& p) override {
    points.emplace_back(p[0], p[1], p[2]);
    return VH(int(points.size()) - 1);
  }
  VH add_vertex() override { return add_vertex(Vec3d(0, 0, 0)); }
  HH add_edge(VH, VH) override { return HH(); }
  FH add_face(const VHandles& idx) override {
    std::vector<int> poly;
    poly.reserve(idx.size());
    for (auto v : idx) poly.push_back(v.idx());
    polygons.push_back(std::move(poly));
    polygon_uv.emplace_back();
    return FH(int(polygons.size()) - 1);
  }
  FH add_face(HH) override { return FH(); }
  void add_face_texcoords(FH f, VH, const std::vector<Vec2f>& tc) override {
    if (!f.is_valid() || size_t(f.idx()) >= polygons.size()) return;
    auto& uv = polygon_uv[f.idx()];
    uv.clear();
    for (const auto& t : tc) uv.emplace_back(t[0], t[1]);
  }
  void add_face_texcoords(FH f, VH v, const std::vector<Vec3f>& tc) override {
    if (tc.empty()) return;  // the OBJ reader calls both overloads; one of them is empty
    std::vector<Vec2f> t2;
    for (const auto& t : tc) t2.emplace_back(t[0], t[1]);
    add_face_texcoords(f, v, t2);
  }
  void set_face_texindex(FH, int id) override { texture_use[id]++; }
  void set_point(VH v, const Vec3f& p) override {
    if (v.is_valid() && size_t(v.idx()) < points.size()) points[v.idx()] = {p[0], p[1], p[2]};
  }
  void set_halfedge(VH, HH) override {}
  void set_normal(VH, const Vec3f&) override {}
  void set_normal(VH, const Vec3d&) override {}
  void set_color(VH v, const Vec3uc& c) override { set_vertex_color(v, Eigen::Vector3f(c[0], c[1], c[2]) / 255.f); }
  void set_color(VH v, const Vec4uc& c) override { set_vertex_color(v, Eigen::Vector3f(c[0], c[1], c[2]) / 255.f); }
  void set_color(VH v, const Vec3f& c) override { set_vertex_color(v, Eigen::Vector3f(c[0], c[1], c[2])); }
  void set_color(VH v, const Vec4f& c) override { set_vertex_color(v, Eigen::Vector3f(c[0], c[1], c[2])); }
  void set_texcoord(VH, const Vec2f&) override {}
  void set_status(VH, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_next(HH, HH) override {}
  void set_face(HH, FH) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HH, const Vec2f&) override {}
  void set_texcoord(VH, const Vec3f&) override {}
  void set_texcoord(HH, const Vec3f&) override {}
  void set_status(HH, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_color(OpenMesh::EdgeHandle, const Vec3uc&) override {}
  void set_color(OpenMesh::EdgeHandle, const Vec4uc&) override {}
  void set_color(OpenMesh::EdgeHandle, const Vec3f&) override {}
  void set_color(OpenMesh::EdgeHandle, const Vec4f&) override {}
  void set_status(OpenMesh::EdgeHandle, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_normal(FH, const Vec3f&) override {}
  void set_normal(FH, const Vec3d&) override {}
  void set_color(FH, const Vec3uc&) override {}
  void set_color(FH, const Vec4uc&) override {}
  void set_color(FH, const Vec3f&) override {}
  void set_color(FH, const Vec4f&) override {}
  void set_status(FH, const OpenMesh::Attributes::StatusInfo&) override {}
  void add_texture_information(int id, std::string name) override { textures[id] = name; }
  size_t n_vertices() const override { return points.size(); }
  size_t n_faces() const override { return polygons.size(); }
  size_t n_edges() const override { return 0; }

 private:
  // Vertices the reader gives no colour stay black once any vertex has one.
  void set_vertex_color(VH v, const Eigen::Vector3f& c) {
    if (!v.is_valid() || size_t(v.idx()) >= points.size()) return;
    if (colors.size() < points.size()) colors.resize(points.size(), Eigen::Vector3f::Zero());
    colors[v.idx()] = c.cwiseMax(0.f).cwiseMin(1.f);
  }
};

// Parses up to three numbers with strtod, which, unlike OpenMesh's stream-based readers,
// understands "nan" and "inf" instead of dropping the line.
int parse_xyz(const char* s, double xyz[3]) {
  int n = 0;
  while (n < 3) {
    char* end = nullptr;
    double x = std::strtod(s, &end);
    if (end == s) break;
    xyz[n++] = x;
    s = end;
  }
  return n;
}

// Text formats are scanned for vertex coordinates here, in double precision: OpenMesh's OBJ and
// OFF readers parse single precision and drop or zero coordinates written as nan/inf, which would
// turn a NaN vertex into a misleading topology error. Throws InputError for non-finite values;
// replaces OpenMesh's points when the count agrees (faces, uv and materials still come from it).
void scan_text_points(const std::string& path, const std::string& text, const std::string& ext, std::vector<Eigen::Vector3d>& pts) {
  TextLines in(text);
  std::vector<Eigen::Vector3d> out;
  std::vector<long> line_of;
  std::string line;
  long lineno = 0;
  auto take = [&](const char* s) {
    double xyz[3];
    if (parse_xyz(s, xyz) < 3) return false;
    out.emplace_back(xyz[0], xyz[1], xyz[2]);
    line_of.push_back(lineno);
    return true;
  };
  if (ext == ".obj") {
    while (in.getline(line)) {
      ++lineno;
      if (line.size() < 2 || line[0] != 'v' || (line[1] != ' ' && line[1] != '\t')) continue;
      if (!take(line.c_str() + 2)) return;
    }
  } else if (ext == ".off" || ext == ".ply") {
    auto next_data_line = [&](std::string& l) {
      while (in.getline(l)) {
        ++lineno;
        auto p = l.find('#');
        if (ext == ".off" && p != std::string::npos) l.resize(p);
        if (l.find_first_not_of(" \t\r") != std::string::npos) return true;
      }
      return false;
    };
    long nv = -1;
    if (!next_data_line(line)) return;
    if (ext == ".off") {
      std::istringstream hs(line);
      std::string magic;
      hs >> magic;
      if (magic != "OFF") return;  // COFF, NOFF, binary OFF: keep OpenMesh's values
      if (!(hs >> nv)) {
        if (!next_data_line(line)) return;
        std::istringstream cs(line);
        if (!(cs >> nv)) return;
      }
    } else {
      // ASCII PLY whose vertex element starts with x, y, z; anything else keeps OpenMesh's values.
      bool ascii = false, in_vertex = false;
      int prop = 0;
      bool xyz_first = false;
      do {
        std::istringstream hs(line);
        std::string w, a, b;
        hs >> w;
        if (w == "format") hs >> a, ascii = a == "ascii";
        if (w == "element") {
          hs >> a >> nv;
          in_vertex = a == "vertex";
          if (!in_vertex && prop == 0) return;  // vertex element must come first
        }
        if (w == "property" && in_vertex) {
          hs >> a >> b;
          if (prop < 3 && b != std::string(1, char('x' + prop))) return;
          if (++prop == 3) xyz_first = true;
        }
        if (w == "end_header") break;
      } while (next_data_line(line));
      if (!ascii || !xyz_first) return;
    }
    for (long i = 0; i < nv; ++i) {
      if (!next_data_line(line) || !take(line.c_str())) return;
    }
  } else {
    return;
  }
  long bad = 0;
  long first = -1;
  for (size_t i = 0; i < out.size(); ++i)
    if (!out[i].allFinite() && !bad++) first = long(i);
  if (bad)
    throw InputError("mesh " + path + " has " + std::to_string(bad) + " vertices with NaN or infinite coordinates, e.g. vertex " +
                     std::to_string(first) + " on line " + std::to_string(line_of[first]) +
                     ". Fix: remove or repair those vertices in the modelling tool");
  if (out.size() != pts.size()) return;
  for (size_t i = 0; i < out.size(); ++i)
    if ((out[i] - pts[i]).norm() > 1e-5 * (1.0 + pts[i].norm())) return;  // not the same vertex order
  pts.swap(out);
}

// The polygon's triangles as corner indices: ear clipping (triangulate_polygon.h) when every corner
// is a point of the file, else a fan (the validation reports the bad index).
std::vector<std::array<int, 3>> polygon_triangles(const std::vector<int>& poly, const std::vector<Eigen::Vector3d>& points) {
  std::vector<Eigen::Vector3d> corners;
  corners.reserve(poly.size());
  for (int v : poly) {
    if (v < 0 || size_t(v) >= points.size() || !points[v].allFinite()) {
      std::vector<std::array<int, 3>> fan;
      for (int k = 1; k + 1 < int(poly.size()); ++k) fan.push_back({0, k, k + 1});
      return fan;
    }
    corners.push_back(points[v]);
  }
  return triangulate_polygon(corners);
}

// The polygons' triangles (and their corners' uv, where every polygon has uv for each corner or
// some have: the others get (0, 0)) appended to the soup, whose points they index.
void add_polygons(const std::vector<std::vector<int>>& polygons, const std::vector<std::vector<Eigen::Vector2d>>& polygon_uv, MeshSoup& soup) {
  bool any_uv = false;
  for (size_t f = 0; f < polygons.size() && f < polygon_uv.size(); ++f)
    if (polygon_uv[f].size() == polygons[f].size()) any_uv = true;
  soup.triangles.reserve(soup.triangles.size() + polygons.size());
  for (size_t f = 0; f < polygons.size(); ++f) {
    const auto& poly = polygons[f];
    const bool has = any_uv && polygon_uv[f].size() == poly.size();
    if (poly.size() < 3) continue;
    if (poly.size() > 3) soup.polygons_triangulated++;
    if (poly.size() == 3 && !any_uv) {
      soup.triangles.push_back({poly[0], poly[1], poly[2]});
      continue;
    }
    for (const auto& t : polygon_triangles(poly, soup.points)) {
      soup.triangles.push_back({poly[t[0]], poly[t[1]], poly[t[2]]});
      if (any_uv)
        for (int c : t) soup.uv.push_back(has ? polygon_uv[f][c] : Eigen::Vector2d(0, 0));
    }
  }
}

// The byte-order mark some editors put before the text of a UTF-8 file.
constexpr const char* kUtf8Bom = "\xEF\xBB\xBF";

// The file's text without its byte-order mark (OpenMesh's readers and the checks would take the
// mark for part of the first line's keyword and lose that line): the mark is dropped in memory, no
// copy of the file is written. A binary STL keeps its 80-byte header as it is.
std::string read_mesh_text(const std::string& path, const std::string& ext) {
  std::string text = read_input_file(path, "mesh", kMaxMeshFileBytes);
  if (text.compare(0, 3, kUtf8Bom) == 0 && (ext != ".stl" || text.compare(3, 5, "solid") == 0)) text.erase(0, 3);
  return text;
}

// A read-only stream over a text in memory, for OpenMesh's stream readers, without a copy.
struct MemoryBuffer : std::streambuf {
  explicit MemoryBuffer(std::string& text) { setg(text.data(), text.data(), text.data() + text.size()); }
  pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
    char* at = dir == std::ios_base::beg ? eback() : dir == std::ios_base::cur ? gptr() : egptr();
    if (off < eback() - at || off > egptr() - at) return pos_type(off_type(-1));
    setg(eback(), at + off, egptr());
    return pos_type(gptr() - eback());
  }
  pos_type seekpos(pos_type pos, std::ios_base::openmode mode) override { return seekoff(off_type(pos), std::ios_base::beg, mode); }
};

// The plain OBJ or OFF the fast readers take (read_plain_text.h), or false for OpenMesh's path.
bool read_plain(const std::string& text, const std::string& ext, MeshSoup& soup) {
  if (ext != ".obj" && ext != ".off" && ext != ".ply") return false;
  if (ext == ".ply") {
    BinaryPly ply;
    if (!read_binary_ply(text, ply)) return false;
    soup.points = std::move(ply.points);
    soup.colors = std::move(ply.colors);
    if (ply.polygons.empty()) soup.triangles = std::move(ply.triangles);
    else add_polygons(ply.polygons, {}, soup);
    return true;
  }
  std::vector<std::vector<int>> polygons;
  if (!(ext == ".obj" ? read_plain_obj(text, soup.points, polygons) : read_plain_off(text, soup.points, polygons))) return false;
  add_polygons(polygons, {}, soup);
  return true;
}

}  // namespace

MeshSoup read_mesh_soup(const std::string& path) {
  check_input_file(path, "mesh");  // a named pipe or a device is refused before anything opens it
  std::error_code ec;
  if (fs::file_size(path, ec) == 0) throw InputError("cannot read mesh " + path + ": the file is empty");
  if (is_point_cloud_file(path)) {  // point_cloud.h; its reader names what is wrong with it first
    read_point_cloud(path);
    throw InputError("cannot read mesh " + path + ": it is a point cloud (points, no faces), which `sdm skeleton`, `info`, `stm`, `encode`, `roundtrip` and `render` take. Fix: give this command a mesh with faces");
  }
  const std::string ext = lower_extension(path);
  if (ext == ".glb" || ext == ".gltf") {
    GltfScene scene = read_gltf(path);
    scene.soup.texture_image = std::move(scene.texture);
    return std::move(scene.soup);
  }
  if (ext != ".obj" && ext != ".off" && ext != ".ply" && ext != ".stl")
    throw InputError("cannot read mesh " + path + ": unknown format '" + ext +
                     "' (supported: .obj, .off, .ply, .stl, .glb, .gltf)");
  std::string text = read_mesh_text(path, ext);

  // A plain OBJ, OFF or PLY is read at once by strict parsers that check what check_mesh_file
  // checks (coordinates finite and within float range, corners and counts within the file);
  // anything else goes through check_mesh_file and OpenMesh, with their messages.
  if (MeshSoup plain; read_plain(text, ext, plain)) return plain;
  check_mesh_file(path, text, ext);  // before any reader trusts the file
  std::string texture;
  if (ext == ".obj") {
    texture = obj_texture(text, path);
    prepare_obj_for_openmesh(text);
  }

  SoupImporter importer;
  OpenMesh::IO::Options opt = OpenMesh::IO::Options::FaceTexCoord;
  opt += OpenMesh::IO::Options::VertexColor;  // the readers pass colours on only when asked
  // OpenMesh's STL stream reader does not tell binary from ASCII itself: the size does (check_stl).
  uint32_t triangles = 0;
  if (ext == ".stl" && text.size() >= 84) std::memcpy(&triangles, text.data() + 80, 4);
  if (ext == ".stl" && text.size() >= 84 && 84 + 50 * std::uintmax_t(triangles) == text.size()) opt += OpenMesh::IO::Options::Binary;
  // OpenMesh reports parse problems on its own streams; the validation report replaces them.
  omerr().disable();
  omlog().disable();
  omout().disable();
  bool ok = false;
  {
    MemoryBuffer buffer(text);
    std::istream stream(&buffer);
    ok = OpenMesh::IO::IOManager().read(stream, ext, importer, opt);
  }
  if (!ok && ext != ".stl") scan_text_points(path, text, ext, importer.points);  // a NaN may be why
  if (!ok) throw InputError("cannot read mesh " + path + ": the " + ext.substr(1) + " reader could not parse it");
  if (importer.points.empty())
    throw InputError("mesh " + path + " has no vertices: the file is empty or not a " + ext.substr(1) + " mesh");

  scan_text_points(path, text, ext, importer.points);

  MeshSoup soup;
  soup.points = std::move(importer.points);
  if (!importer.colors.empty()) {
    importer.colors.resize(soup.points.size(), Eigen::Vector3f::Zero());
    soup.colors = std::move(importer.colors);
  }
  add_polygons(importer.polygons, importer.polygon_uv, soup);
  soup.texture = texture;
  return soup;
}

std::vector<char> used_points(const MeshSoup& soup) {
  std::vector<char> used(soup.points.size(), 0);
  for (const auto& t : soup.triangles)
    for (int v : t) used[v] = 1;
  return used;
}

Mesh build_mesh(const MeshSoup& soup, const EdgeTable* table) {
  Mesh mesh;
  const std::vector<char> used = used_points(soup);
  // The faces go in through add_faces: the connectivity add_face would build one face at a time,
  // element for element (the rest of the pipeline inherits its order), in a third of the time.
  std::vector<int> index(soup.points.size(), -1);
  int n = 0;
  for (size_t i = 0; i < soup.points.size(); ++i)
    if (used[i]) index[i] = n++;  // isolated vertices are dropped; validation reports them
  mesh.reserve(size_t(n), soup.triangles.size() * 3 / 2 + 3, soup.triangles.size());
  for (size_t i = 0; i < soup.points.size(); ++i)
    if (used[i]) mesh.add_vertex(Mesh::Point(soup.points[i].x(), soup.points[i].y(), soup.points[i].z()));
  std::vector<std::array<int, 3>> corners(soup.triangles.size());
  for (size_t f = 0; f < soup.triangles.size(); ++f)
    for (size_t c = 0; c < 3; ++c) corners[f][c] = index[size_t(soup.triangles[f][c])];
  if (!add_faces(mesh, corners, table))
    for (size_t f = 0; f < corners.size(); ++f) {
      const auto& t = corners[f];
      if (!mesh.add_face(Mesh::VertexHandle(t[0]), Mesh::VertexHandle(t[1]), Mesh::VertexHandle(t[2])).is_valid())
        throw InputError("face " + std::to_string(f) + " cannot be added to a manifold mesh (validate the mesh first)");
    }
  if (soup.uv.size() == 3 * soup.triangles.size() && !soup.triangles.empty()) {
    mesh.request_halfedge_texcoords2D();
    // Face f's halfedge into its corner c carries corner c's uv.
    for (auto f : mesh.faces())
      for (auto h : mesh.fh_range(f)) {
        const int to = h.to().idx();
        for (size_t c = 0; c < 3; ++c)
          if (corners[size_t(f.idx())][c] == to) {
            const auto& uv = soup.uv[3 * size_t(f.idx()) + c];
            mesh.set_texcoord2D(h, Mesh::TexCoord2D(uv.x(), uv.y()));
          }
      }
  }
  return mesh;
}

MeshSoup mesh_to_soup(const Mesh& mesh) {
  MeshSoup soup;
  soup.points.reserve(mesh.n_vertices());
  for (auto v : mesh.vertices()) soup.points.push_back(point(mesh, v));
  for (auto f : mesh.faces()) {
    std::array<int, 3> t{};
    int c = 0;
    for (auto v : mesh.fv_range(f)) t[c++] = v.idx();
    soup.triangles.push_back(t);
  }
  return soup;
}

Mesh mesh_from_arrays(const Eigen::MatrixX3d& V, const Eigen::MatrixX3i& F, const Eigen::MatrixX2d& uv, const std::string& what) {
  if (uv.rows() != 0 && uv.rows() != 3 * F.rows())
    throw InputError(what + ": uv has " + std::to_string(uv.rows()) + " rows; give one per face corner (" +
                     std::to_string(3 * F.rows()) + ") or none");
  MeshSoup soup;
  soup.points.reserve(V.rows());
  for (Eigen::Index i = 0; i < V.rows(); ++i) soup.points.push_back(V.row(i).transpose());
  soup.triangles.reserve(F.rows());
  for (Eigen::Index f = 0; f < F.rows(); ++f) soup.triangles.push_back({F(f, 0), F(f, 1), F(f, 2)});
  for (Eigen::Index c = 0; c < uv.rows(); ++c) soup.uv.push_back(uv.row(c).transpose());
  MeshReport report = validate_mesh(soup);
  if (!report.usable()) throw InputError(report.refusal(what));
  const std::vector<char> used = used_points(soup);
  const auto unused = std::find(used.begin(), used.end(), char(0));
  if (unused != used.end())
    throw InputError(what + ": vertex " + std::to_string(unused - used.begin()) + " is used by no face (" +
                     std::to_string(std::count(used.begin(), used.end(), char(0))) +
                     " such vertices); remove them so that vertex indices stay those of the arrays");
  orient_outward(soup, report);
  return build_mesh(soup);
}

namespace {

// Text of the numbers appended to a buffer that goes out by the megabyte: the positions with the
// shortest digits that read back to the same double (std::to_chars, as off_text), not printf's 17
// (a level-4 decode's 880k faces: the writer took a fifth of the command).
class ObjText {
 public:
  explicit ObjText(std::ofstream& out) : out_(out) { buf_.reserve(kFlush + 256); }
  ~ObjText() { flush(); }
  ObjText& operator<<(const char* s) { return buf_ += s, *this; }
  ObjText& operator<<(char c) { return buf_ += c, *this; }
  template <class Number>
  ObjText& operator<<(Number x) {
    char b[32];
    buf_.append(b, std::to_chars(b, b + sizeof b, x).ptr);
    return *this;
  }
  void end_line() {
    buf_ += '\n';
    if (buf_.size() >= kFlush) flush();
  }
  void flush() {
    out_.write(buf_.data(), std::streamsize(buf_.size()));
    buf_.clear();
  }

 private:
  static constexpr size_t kFlush = size_t(1) << 20;
  std::ofstream& out_;
  std::string buf_;
};

void write_obj(const Mesh& mesh, const std::string& tmp, const std::string& final_path, const std::string& texture) {
  const bool uv = mesh.has_halfedge_texcoords2D();
  std::ofstream out(tmp);
  out << "# written by sdm\n";
  const fs::path fp(final_path);
  const std::string mtl_name = fp.stem().string() + ".mtl";
  if (uv && !texture.empty()) out << "mtllib " << mtl_name << "\nusemtl sdm_texture\n";
  {
    ObjText text(out);
    for (auto v : mesh.vertices()) {
      const auto& p = mesh.point(v);
      text << "v " << p[0] << ' ' << p[1] << ' ' << p[2];
      text.end_line();
    }
    if (uv) {
      for (auto f : mesh.faces())
        for (auto h : mesh.fh_range(f)) {
          const auto& t = mesh.texcoord2D(h);
          text << "vt " << t[0] << ' ' << t[1];
          text.end_line();
        }
    }
    int k = 1;
    for (auto f : mesh.faces()) {
      text << 'f';
      for (auto h : mesh.fh_range(f)) {
        text << ' ' << mesh.to_vertex_handle(h).idx() + 1;
        if (uv) text << '/' << k++;
      }
      text.end_line();
    }
  }
  out.close();
  if (!out) throw std::runtime_error("cannot write " + final_path);
  if (uv && !texture.empty()) {
    fs::path tex(texture);
    std::string rel = tex.is_absolute() ? fs::relative(tex, fs::absolute(fp).parent_path()).string() : tex.string();
    write_text_file((fp.parent_path() / mtl_name).string(),
                    "# written by sdm\nnewmtl sdm_texture\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nillum 1\nmap_Kd " + rel + "\n");
  }
}

// OpenMesh's writers do not check their stream once it is open (a full disk gives a truncated
// file and success): they write into memory here and the bytes go out through a checked write.
void write_through_openmesh(const Mesh& mesh, const std::string& tmp, const std::string& path, const std::string& ext,
                            OpenMesh::IO::Options opt) {
  omerr().disable();
  std::ostringstream os(std::ios::out | std::ios::binary);
  if (!OpenMesh::IO::write_mesh(mesh, os, ext, opt, 17) || !os) throw std::runtime_error("cannot write " + path);
  const std::string bytes = os.str();
  write_bytes_checked(tmp, bytes.data(), bytes.size(), path);
}

}  // namespace

void write_mesh(const Mesh& mesh, const std::string& path, const std::string& texture) {
  const std::string ext = lower_extension(path);
  if (ext == ".glb" || ext == ".gltf") {
    write_gltf(mesh, path, texture);
    return;
  }
  if (ext != ".obj" && ext != ".ply" && ext != ".off" && ext != ".stl")
    throw InputError("cannot write " + path + ": unknown format '" + ext + "' (use .obj, .ply, .off, .stl, .glb or .gltf)");
  write_atomically(path, [&](const std::string& tmp) {
    if (ext == ".obj") {
      // OpenMesh's OBJ writer names no texture map in its material, so OBJ is written here.
      write_obj(mesh, tmp, path, texture);
      return;
    }
    if (ext == ".off" || ext == ".ply") {
      // OpenMesh's OFF and PLY writers round positions to float (write_positions.h).
      const std::string bytes = ext == ".off" ? off_text(mesh) : ply_bytes(mesh);
      write_bytes_checked(tmp, bytes.data(), bytes.size(), path);
      return;
    }
    const OpenMesh::IO::Options opt = OpenMesh::IO::Options::Binary;  // STL
    write_through_openmesh(mesh, tmp, path, ext, opt);
  });
}

void write_colored_ply(const Mesh& mesh, const std::vector<Eigen::Vector3f>& colors, const std::string& path) {
  if (lower_extension(path) != ".ply")
    throw InputError("cannot write vertex colours to " + path + ": they are written as PLY, so name a .ply file");
  if (colors.size() != mesh.n_vertices())
    throw InputError("cannot write " + path + ": " + std::to_string(colors.size()) + " colours for " + std::to_string(mesh.n_vertices()) +
                     " vertices");
  Mesh copy = mesh;
  copy.request_vertex_colors();
  for (auto v : copy.vertices()) {
    const Eigen::Vector3f c = (255.f * colors[v.idx()].cwiseMax(0.f).cwiseMin(1.f)).array().round();
    copy.set_color(v, Mesh::Color(uint8_t(c[0]), uint8_t(c[1]), uint8_t(c[2])));
  }
  write_atomically(path, [&](const std::string& tmp) {
    OpenMesh::IO::Options opt = OpenMesh::IO::Options::Binary;
    opt += OpenMesh::IO::Options::VertexColor;
    write_through_openmesh(copy, tmp, path, ".ply", opt);
  });
}

Eigen::MatrixX3d vertex_matrix(const Mesh& mesh) {
  Eigen::MatrixX3d V(mesh.n_vertices(), 3);
  for (auto v : mesh.vertices()) V.row(v.idx()) = point(mesh, v).transpose();
  return V;
}

Eigen::MatrixX3i face_matrix(const Mesh& mesh) {
  Eigen::MatrixX3i F(mesh.n_faces(), 3);
  for (auto f : mesh.faces()) {
    int c = 0;
    for (auto v : mesh.fv_range(f)) F(f.idx(), c++) = v.idx();
  }
  return F;
}

void bounding_box(const Mesh& mesh, Eigen::Vector3d& lo, Eigen::Vector3d& hi) {
  lo.setConstant(std::numeric_limits<double>::infinity());
  hi.setConstant(-std::numeric_limits<double>::infinity());
  for (auto v : mesh.vertices()) {
    lo = lo.cwiseMin(point(mesh, v));
    hi = hi.cwiseMax(point(mesh, v));
  }
}

double bounding_box_diagonal(const Mesh& mesh) {
  Eigen::Vector3d lo, hi;
  bounding_box(mesh, lo, hi);
  return mesh.n_vertices() ? (hi - lo).norm() : 0.0;
}

}  // namespace sdm
