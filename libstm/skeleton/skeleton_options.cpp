// The skeleton method's names (skeleton_options.h).
#include "libstm/skeleton/skeleton_options.h"

namespace sdm {

const char* to_string(SkeletonMethod method) {
  switch (method) {
    case SkeletonMethod::automatic:
      return "auto";
    case SkeletonMethod::contraction:
      return "contraction";
    case SkeletonMethod::medial:
      return "medial";
  }
  return "auto";
}

}  // namespace sdm
