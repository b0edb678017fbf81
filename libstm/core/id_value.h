#pragma once
/// The items of the repeatable ID=VALUE options (--lod-segment 3=1, --scale-radius 3=1.2, --rotate
/// 4=x,30, --match 3=5), read in one way: each function throws InputError(form), `form` the message
/// that names the option and the form it expects.
#include <string>

namespace sdm {

struct IdValue {
  int id = 0;
  std::string value;  ///< the text after the '='
};

/// The whole number before the first '=' and the text after it; InputError(form) for an item without
/// '=' or whose ID is not a whole number.
IdValue parse_id_value(const std::string& item, const std::string& form);
/// All of `text` as a whole number (std::stoi's leading blanks and sign allowed), else InputError(form).
int parse_whole_number(const std::string& text, const std::string& form);
/// All of `text` as a finite number, else InputError(form).
double parse_finite_number(const std::string& text, const std::string& form);

}  // namespace sdm
