#pragma once
/// Skeleton displacement map encoding (paper 5, DESIGN 4.8): for every texel of every segment's
/// rectangle, a distance along the texel's capsule ray (capsule_ray.h) to the surface (D, model
/// units) and whether that crossing lies on the segment's own faces (A). The layout and the base
/// mesh (base_mesh.h) travel in the header, so the file alone rebuilds the surface.
///
/// D is not simply the first crossing: the decoder places each point of a base face on the ray
/// through the same point of the face's reference triangle (the face drawn on the segment's
/// capsule), so each texel is encoded for the base face its ray passes through (or the nearest one,
/// for texels between and around them): D is the crossing nearest the point of that flat base face,
/// or, when no crossing is within half the face's longest edge (a ray grazing a saddle), that
/// point's foot on the ray. Near junctions the first crossing is often another sheet of the surface.
#include "libstm/core/progress.h"
#include "libsdm/map/sdm_exr.h"
#include "libsdm/map/texels.h"
#include "libstm/layout/layout.h"
#include "libstm/mesh/mesh.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace sdm {

struct EncodeOptions {
  int base_vertices = 0;  ///< size of the base mesh (0: chosen from the mesh)
  Progress progress;
  /// Texels no base face reads: the first crossing of their ray with the segment's faces (else any),
  /// for pictures of the map (`sdm encode --png`); false leaves them NaN, as every file stores and
  /// every reader sees them (format 3), and saves two ray casts each; the file is byte for byte the
  /// same either way.
  bool fill_unread = true;
  /// Base faces whose points decode (at level 3) farther than flat_above (a fraction of the
  /// bounding-box diagonal) from the input are placed on their flat triangle where it lies closer;
  /// where faces still decode farther than refine_above, the source's vertices nearest them are kept
  /// and the base mesh is decimated again, up to refine_rounds times (flat_above <= 0: the first
  /// base mesh as it is, no check).
  double flat_above = 0.0025;
  double refine_above = 0.0075;
  int refine_rounds = 2;
};

struct EncodeStats {
  long texels = 0;      ///< texels inside the segments' rectangles
  long own_hits = 0;    ///< A = 1: D is a crossing with the segment's own faces
  long other_hits = 0;  ///< A = 0, D is a crossing with another segment's faces
  long filled = 0;      ///< A = 0, D is the foot of the base face's point (no crossing near it)
  int base_faces = 0;
  int flat_faces = 0;   ///< base faces placed on their flat triangle (base_mesh.h)
  int decimations = 0;  ///< base meshes made: 1, plus one per refinement (EncodeOptions::refine_above)
  long kept = 0;        ///< vertices of the input kept in the last base mesh by the refinements
};

/// Texels outside every rectangle get D = 0, A = 0. The layout must have been computed for `mesh`.
SdmImage encode_sdm(const Mesh& mesh, const Layout& layout, const EncodeOptions& options = {}, EncodeStats* stats = nullptr);

}  // namespace sdm
