#include "libstm/layout/layout_json.h"

#include "libstm/core/atomic_file.h"
#include "libstm/core/errors.h"
#include "libstm/core/input_file.h"
#include "libstm/core/json_int.h"
#include "libstm/core/limits.h"
#include "libstm/layout/segments.h"

#include <cmath>
#include <cstdint>

namespace sdm {

namespace {

nlohmann::json vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
Eigen::Vector3d vec(const nlohmann::json& j) { return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()}; }

}  // namespace

nlohmann::json layout_to_json(const Layout& L) {
  nlohmann::json j;
  j["format"] = "sdm-layout";
  j["version"] = 1;
  j["size"] = L.size;
  j["margin"] = L.margin;
  j["scale"] = L.scale;
  j["coverage"] = L.coverage;
  j["coverage_inner"] = L.coverage_inner;
  j["assignment"] = L.assignment;
  j["skeleton"] = skeleton_to_json(L.skeleton);
  j["segments"] = nlohmann::json::array();
  for (const auto& g : L.segments) {
    nlohmann::json s;
    s["edge"] = g.edge;
    s["a"] = g.a;
    s["b"] = g.b;
    s["axis"] = vec(g.axis);
    s["e1"] = vec(g.e1);
    s["e2"] = vec(g.e2);
    s["radius"] = g.radius;
    s["cap"] = g.cap;
    s["length"] = g.length;
    s["area"] = g.area;
    s["weight"] = g.weight;
    s["rect"] = {g.x, g.y, g.w, g.h};
    s["rotated"] = g.rotated;
    s["d"] = g.d;
    if (g.extend_a > 0 || g.extend_b > 0) s["extend"] = {g.extend_a, g.extend_b};
    s["neighbours_a"] = g.neighbours_a;
    s["neighbours_b"] = g.neighbours_b;
    j["segments"].push_back(s);
  }
  return j;
}

namespace {

std::string segment_problem(const Layout& L, size_t s) {
  const LayoutSegment& g = L.segments[s];
  const auto& e = L.skeleton.edges[s];
  const int nn = int(L.skeleton.nodes.size()), ns = int(L.segments.size());
  const bool ends_ok = g.a >= 0 && g.a < nn && g.b >= 0 && g.b < nn && ((g.a == e[0] && g.b == e[1]) || (g.a == e[1] && g.b == e[0]));
  if (!ends_ok || g.edge != int(s)) return "does not match its skeleton edge";
  // 64-bit sums: a rectangle near INT_MAX must not wrap around into the atlas.
  const int64_t right = int64_t(g.x) + (g.rotated ? g.h : g.w), top = int64_t(g.y) + (g.rotated ? g.w : g.h);
  if (g.w <= 0 || g.h <= 0 || g.x < 0 || g.y < 0 || right > L.size || top > L.size) return "lies outside the atlas";
  for (const Eigen::Vector3d* v : {&g.axis, &g.e1, &g.e2})
    if (!v->allFinite() || std::abs(v->norm() - 1) > 1e-6) return "has a frame that is not made of unit vectors";
  if (std::abs(g.axis.dot(g.e1)) > 1e-6 || std::abs(g.axis.dot(g.e2)) > 1e-6 || std::abs(g.e1.dot(g.e2)) > 1e-6)
    return "has a frame that is not orthogonal";
  if (!(g.radius > 0) || !std::isfinite(g.radius)) return "has radius " + number(g.radius) + " (it must be positive)";
  if (!(g.cap >= 0) || !std::isfinite(g.cap) || !(g.length >= 0) || !std::isfinite(g.length))
    return "has a negative or non-finite cap or length";
  if (!(g.weight > 0) || !std::isfinite(g.weight)) return "has a weight that is not positive";
  if (!(g.d >= 0) || !(g.d <= 0.5 * g.w + 1e-9)) return "has a cap of " + number(g.d) + " texels outside 0..w/2";
  // The rectangle is the capsule at the layout's scale, grown by packing (measured 0.99-1.34x on
  // Spot and the capsule, 2.18x on a Spot with its head pushed into its body): a radius or length
  // tampered by 10x decoded a "closed 2-manifold" off by model units.
  if (!(g.extend_a >= 0 && g.extend_a <= kMaxCapExtension) || !(g.extend_b >= 0 && g.extend_b <= kMaxCapExtension))
    return "has capsule extensions " + number(g.extend_a) + ", " + number(g.extend_b) + " outside 0.." + number(kMaxCapExtension) + " radii";
  const double around = 2 * M_PI * g.radius * L.scale * g.weight, along = capsule_length(g) * L.scale * g.weight;
  if (g.h < 0.5 * around - 1 || g.h > 4 * around + 1 || g.w < 0.5 * along - 1 || g.w > 4 * along + 1)
    return "has a rectangle of " + std::to_string(g.w) + "x" + std::to_string(g.h) + " texels for a capsule of " + number(along) + "x" +
           number(around) + " at the layout's scale: its radius, length or scale was altered";
  // The axis runs from node a to node b (segment_frames.h).
  const Eigen::Vector3d ab = L.skeleton.nodes[g.b] - L.skeleton.nodes[g.a];
  if ((g.axis - ab / ab.norm()).norm() > 1e-6) return "has an axis that does not run from its node a to its node b";
  for (const auto* nb : {&g.neighbours_a, &g.neighbours_b})
    for (int o : *nb)
      if (o < 0 || o >= ns) return "names neighbour segment " + std::to_string(o) + " of " + std::to_string(ns);
  return "";
}

// Checks what compute_layout guarantees, so that a crafted file is refused before anything indexes
// the atlas with its numbers (see layout_json.h).
void check_layout(const Layout& L) {
  if (L.size < 1 || L.size > kMaxImageSide)
    throw InputError("not a valid sdm layout: atlas size " + std::to_string(L.size) + " is outside 1.." + std::to_string(kMaxImageSide));
  if (L.margin < 0 || L.margin > L.size)
    throw InputError("not a valid sdm layout: margin " + std::to_string(L.margin) + " is outside 0.." + std::to_string(L.size));
  if (!(L.scale > 0) || !std::isfinite(L.scale)) throw InputError("not a valid sdm layout: scale must be positive");
  if (L.segments.size() != L.skeleton.edges.size())
    throw InputError("not a valid sdm layout: " + std::to_string(L.segments.size()) + " segments for " +
                     std::to_string(L.skeleton.edges.size()) + " skeleton edges");
  for (size_t s = 0; s < L.segments.size(); ++s) {
    const std::string why = segment_problem(L, s);
    if (!why.empty()) throw InputError("not a valid sdm layout: segment " + std::to_string(s) + " " + why);
  }
}

}  // namespace

Layout layout_from_json(const nlohmann::json& j) {
  Layout L;
  try {
    if (j.value("format", std::string()) != "sdm-layout") throw InputError("not an sdm layout (format is not \"sdm-layout\")");
    if (json_int(j.at("version")) != 1)
      throw InputError("sdm layout version " + std::to_string(json_int(j.at("version"))) + " is not supported (this build reads 1)");
    L.size = json_int(j.at("size"));
    L.margin = json_int(j.at("margin"));
    L.scale = j.at("scale").get<double>();
    L.coverage = j.value("coverage", 0.0);
    L.coverage_inner = j.value("coverage_inner", 0.0);
    L.assignment = j.contains("assignment") ? json_int(j.at("assignment")) : 1;
    if (L.assignment < 1 || L.assignment > 3)
      throw InputError("layout assignment rule " + std::to_string(L.assignment) + " is not supported (this build knows 1 to 3)");
    L.skeleton = skeleton_from_json(j.at("skeleton"));
    for (const auto& s : j.at("segments")) {
      LayoutSegment g;
      g.edge = json_int(s.at("edge"));
      g.a = json_int(s.at("a"));
      g.b = json_int(s.at("b"));
      g.axis = vec(s.at("axis"));
      g.e1 = vec(s.at("e1"));
      g.e2 = vec(s.at("e2"));
      g.radius = s.at("radius").get<double>();
      g.cap = s.at("cap").get<double>();
      g.length = s.at("length").get<double>();
      g.area = s.value("area", 0.0);
      g.weight = s.value("weight", 1.0);
      const auto& r = s.at("rect");
      g.x = json_int(r.at(0)), g.y = json_int(r.at(1)), g.w = json_int(r.at(2)), g.h = json_int(r.at(3));
      g.rotated = s.at("rotated").get<bool>();
      g.d = s.at("d").get<double>();
      if (s.contains("extend")) {
        if (L.assignment < 3)
          throw InputError("segment " + std::to_string(L.segments.size()) + " has capsule extensions, which assignment rule " +
                           std::to_string(L.assignment) + " does not have");
        g.extend_a = s["extend"].at(0).get<double>(), g.extend_b = s["extend"].at(1).get<double>();
      }
      if (s.contains("neighbours_a")) g.neighbours_a = json_ints(s["neighbours_a"]);
      if (s.contains("neighbours_b")) g.neighbours_b = json_ints(s["neighbours_b"]);
      L.segments.push_back(g);
    }
  } catch (const nlohmann::json::exception& e) {
    throw InputError(std::string("not a valid sdm layout: ") + e.what());
  }
  check_layout(L);
  return L;
}

void write_layout_json(const Layout& L, const std::string& path) { write_text_file(path, layout_to_json(L).dump(1) + "\n"); }

Layout read_layout_json(const std::string& path, const ReadBudget& budget) {
  const nlohmann::json j = nlohmann::json::parse(read_input_file(path, "layout", kMaxJsonFileBytes, budget, kJsonBytesPerFileByte), nullptr, false);
  if (j.is_discarded()) throw InputError("cannot read layout " + path + ": not JSON");
  try {
    return layout_from_json(j);
  } catch (const InputError& e) {
    throw InputError("layout " + path + ": " + e.what());
  }
}

}  // namespace sdm
