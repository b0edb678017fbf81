#pragma once
/// The fixed-function GL state the render passes draw with (render_atlas, render_mesh, render_stm),
/// set in one place.

namespace sdm {

/// Opaque, depth-tested drawing into the bound framebuffer: blending, face culling and the scissor
/// test off; the depth test on with GL_LESS and depth writes on; every colour channel written.
/// Multisampling is left to the caller (it depends on the framebuffer and the pass).
/// \pre a GL context is current (gl_context.h).
void set_opaque_depth_state();

}  // namespace sdm
