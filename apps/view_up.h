#pragma once
// Which way is up in a model's file, for the commands that draw it (render, the previews of
// transfer and roundtrip): --up AXIS, else what the file's format says (glTF: +y by its
// specification), else unknown (render then keeps the world's +y; previews stand the model in its
// principal axes).
#include <CLI/CLI.hpp>
#include <Eigen/Core>

#include <string>

namespace sdm::cli {

struct ViewUp {
  Eigen::Vector3d axis = Eigen::Vector3d::UnitY();
  std::string name = "+y";  // "+x" ... "-z"
  std::string from;         // "--up", "glTF specification" or "" (unknown: +y assumed)
  bool known() const { return !from.empty(); }
};

//! Adds an up option (`flag`, e.g. "--up") for `whose` model, bound to `value`: x, y, z, +x, ..., -z
//! or auto (the default: the file's own when its format states one).
void add_up_option(CLI::App* app, std::string& value, const std::string& flag = "--up", const std::string& whose = "the model");

//! The up of the model read from `mesh_path` given the option's `value`.
//! \throw InputError naming the option and the accepted values for any other value.
ViewUp view_up(const std::string& value, const std::string& mesh_path, const std::string& flag = "--up");

}  // namespace sdm::cli
