#version 450 core
// Surface colour (flat, texture or per vertex) times optional headlight shading.
in vec3 v_view_position;
in vec3 v_normal;
in vec2 v_uv;
in vec3 v_color;

uniform int u_color_source;  // 0: u_color, 1: u_texture at the mesh's uv, 2: the vertices' colours
uniform vec3 u_color;
uniform sampler2D u_texture;
uniform bool u_lit;
uniform bool u_orthographic;
uniform float u_ambient;

layout(location = 0) out vec4 out_color;

void main() {
  // Sampled unconditionally: derivatives for mip selection need uniform control flow.
  vec3 tex = texture(u_texture, v_uv).rgb;
  vec3 c = u_color_source == 1 ? tex : u_color_source == 2 ? v_color : u_color;
  if (u_lit) {
    vec3 n = normalize(v_normal);
    vec3 l = u_orthographic ? vec3(0.0, 0.0, 1.0) : normalize(-v_view_position);
    // Two-sided: a surface seen from behind is lit as its front.
    c *= u_ambient + (1.0 - u_ambient) * abs(dot(n, l));
  }
  // Alpha 1 marks coverage; the clear colour is 0, so after the multisample resolve alpha is the
  // covered fraction and rgb is premultiplied, ready to composite over the background on the CPU.
  out_color = vec4(c, 1.0);
}
