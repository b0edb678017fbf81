#include "libstm/core/id_value.h"

#include "libstm/core/errors.h"

#include <cmath>

namespace sdm {

int parse_whole_number(const std::string& text, const std::string& form) {
  size_t used = 0;
  int i = 0;
  try {
    i = std::stoi(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size()) throw InputError(form);
  return i;
}

double parse_finite_number(const std::string& text, const std::string& form) {
  size_t used = 0;
  double x = NAN;
  try {
    x = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != text.size() || !std::isfinite(x)) throw InputError(form);
  return x;
}

IdValue parse_id_value(const std::string& item, const std::string& form) {
  const auto eq = item.find('=');
  if (eq == std::string::npos) throw InputError(form);
  return {parse_whole_number(item.substr(0, eq), form), item.substr(eq + 1)};
}

}  // namespace sdm
