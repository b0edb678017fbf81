#pragma once
/// Integers read from companion files (skeleton, layout, SDM header). nlohmann's get<int>() converts
/// a JSON float such as 3e12 with a cast that is undefined beyond int's range (found by fuzzing the
/// skeleton and layout readers); these accept whole numbers within int only and refuse the rest.
#include "libstm/core/errors.h"

#include <nlohmann/json.hpp>

#include <climits>
#include <cmath>
#include <string>
#include <vector>

namespace sdm {

/// `v` as an int; throws InputError naming the value unless it is a whole number in int's range
/// (an integer, or a float with no fraction such as 3.0).
inline int json_int(const nlohmann::json& v) {
  if (v.is_number_integer()) {
    const auto i = v.get<nlohmann::json::number_integer_t>();
    if (i >= INT_MIN && i <= INT_MAX) return int(i);
  } else if (v.is_number_unsigned()) {
    const auto u = v.get<nlohmann::json::number_unsigned_t>();
    if (u <= nlohmann::json::number_unsigned_t(INT_MAX)) return int(u);
  } else if (v.is_number_float()) {
    const double d = v.get<double>();
    if (std::isfinite(d) && d == std::floor(d) && d >= INT_MIN && d <= INT_MAX) return int(d);
  }
  throw InputError("expected a whole number within " + std::to_string(INT_MIN) + ".." + std::to_string(INT_MAX) + ", found " +
                   v.dump().substr(0, 40));
}

/// An array of such integers.
inline std::vector<int> json_ints(const nlohmann::json& v) {
  if (!v.is_array()) throw InputError("expected an array of whole numbers, found " + v.dump().substr(0, 40));
  std::vector<int> out;
  out.reserve(v.size());
  for (const auto& x : v) out.push_back(json_int(x));
  return out;
}

}  // namespace sdm
