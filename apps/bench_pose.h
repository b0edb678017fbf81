#pragma once
// sdm bench --pose (docs/BENCHMARKS.md, "Posing"): a model posed like another scan of the same
// body through its SDM's skeleton, against linear blend skinning of the model with the same motions.
#include <string>
#include <vector>

namespace sdm::cli {

// `pairs`: SOURCE TARGET [SOURCE TARGET ...], meshes with the same connectivity (vertex i of one is
// vertex i of the other, as in FAUST). Prints a table (or JSON with `json`); `machine` names the
// machine. Returns the exit code.
int run_pose_bench(const std::vector<std::string>& pairs, int size, bool json, const std::string& machine);

}  // namespace sdm::cli
