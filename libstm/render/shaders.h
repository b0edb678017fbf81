#pragma once
/// GLSL sources embedded at build time (cmake/embed_shaders.cmake turns shaders/NAME.glsl into
/// a string constant), so the binary runs from any folder.
#include <string>

namespace sdm {

/// The text of shaders/NAME.glsl, e.g. shader_source("mesh.vert.glsl").
/// \throw std::runtime_error for an unknown name.
const char* shader_source(const std::string& name);

}  // namespace sdm
