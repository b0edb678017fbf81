#pragma once
/// Faces -> segments as a layout's shaders assign them (DESIGN 4.4).
#include "libstm/layout/layout.h"
#include "libstm/mesh/mesh.h"
#include "libstm/skeleton/skeleton.h"

#include <vector>

namespace sdm {

/// assign_faces_with_radii (segments.h) with the layout's radii (LayoutSegment::radius, segment by
/// segment) and its rule (Layout::assignment), on the layout's skeleton.
std::vector<int> assign_faces(const Mesh& mesh, const Layout& layout);
/// The same with `skeleton`: the layout's skeleton with another mesh's vertex map (a base mesh's).
/// \pre `skeleton` has the layout's graph and `mesh`'s vertex map.
std::vector<int> assign_faces(const Mesh& mesh, const Layout& layout, const Skeleton& skeleton);

}  // namespace sdm
