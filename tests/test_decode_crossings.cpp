// Decoded surfaces cross themselves no more than their input does (DESIGN 4.8): the points move
// from the flat base along the base mesh's interpolated normals, and folds left where the
// displacement is large against the decoded edges are untangled (untangle_decoded.h).
#include "libsdm/decode/decode_sdm.h"
#include "libsdm/encode/encode_sdm.h"
#include "libstm/layout/compute_layout.h"
#include "libstm/mesh/load_mesh.h"
#include "libstm/mesh/mesh_geometry.h"
#include "libstm/mesh/self_intersections.h"
#include "libstm/mesh/surface_distance.h"
#include "libstm/skeleton/extract_skeleton.h"

#include <catch2/catch.hpp>
#include <cstdio>

using namespace sdm;

namespace {

long crossing_pairs(const Mesh& m) { return long(crossing_face_pairs(vertex_matrix(m), face_matrix(m)).size()); }

}  // namespace

// Spot (examples/data, no crossing pair) at 512: decoded along the capsules' rays, its level 2 and
// 3 crossed 224 and 1375 face pairs (CGAL's count; the same with crossing_face_pairs), at the base
// edges between segments and where a segment's rays fan out under large displacements.
TEST_CASE("Spot decoded at levels 2 and 3 crosses itself no more than its input", "[decode_crossings]") {
  const Mesh spot = load_mesh(std::string(SDM_EXAMPLES) + "/spot/spot_triangulated.obj").mesh;
  const long input = crossing_pairs(spot);
  CHECK(input == 0);
  LayoutOptions lo;
  lo.size = 512;
  const SdmImage image = encode_sdm(spot, compute_layout(spot, extract_skeleton(spot), lo));
  for (int level : {2, 3}) {
    DecodeOptions o;
    o.level = level;
    DecodeTrace trace;
    const Mesh out = decode_sdm(image, o, &trace);
    const long decoded = crossing_pairs(out);
    const SurfaceDistance d = surface_distance(spot, out, 100000);
    std::printf("spot 512 level %d: %ld crossing pairs (input %ld), %ld folded pairs untangled, %ld points moved; RMS %.4f %% Hausdorff %.3f %%\n",
                level, decoded, input, trace.untangle.crossing, trace.untangle.moved, 100 * d.rms / d.diagonal,
                100 * d.hausdorff / d.diagonal);
    CHECK(decoded <= input);
    CHECK(trace.untangle.left == 0);
    CHECK(d.rms / d.diagonal <= 0.0005);  // the round trip bound of the real meshes (test_decode_sdm)
    CHECK(d.hausdorff / d.diagonal <= 0.01);
  }
}

// crossing_face_pairs counts what CGAL's PMP::self_intersections counts: besides pairs without a
// common vertex, a pair with one common vertex whose other edges pass through each other.
TEST_CASE("Crossing pairs include faces that share a vertex and fold through each other", "[decode_crossings]") {
  Eigen::MatrixX3d V(5, 3);
  // Two triangles sharing vertex 0; the second passes through the first's middle.
  V << 0, 0, 0, 2, 0, 0, 0, 2, 0, 0.5, 0.5, -1, 0.5, 0.5, 1;
  Eigen::MatrixX3i F(2, 3);
  F << 0, 1, 2, 0, 3, 4;
  CHECK(crossing_face_pairs(V, F).size() == 1);
  CHECK(find_self_intersections(V, F).pairs == 0);  // the encoder's check of its input leaves such pairs out
  V.row(3) << 0.5, 0.5, 0.5;                          // now above the first face: no crossing
  CHECK(crossing_face_pairs(V, F).empty());
}
