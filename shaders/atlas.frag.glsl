#version 450 core
// Atlas pass of render_atlas: fills a texel of a segment's rectangle (or its margin) with the
// source texture at the interpolated uv, or with the interpolated float values.
flat in vec4 v_clip;
in vec4 v_value;

uniform int u_mode;  // 0: colour = u_source at v_value.xy; 1: float target = v_value
uniform sampler2D u_source;

layout(location = 0) out vec4 out_color;  // alpha 1 marks a covered texel
layout(location = 1) out vec4 out_value;

void main() {
  // Sampled before the discard: derivatives (mip selection in the source) need uniform control flow.
  vec4 c = texture(u_source, v_value.xy);
  // A triangle drawn for one rectangle must not spill into another one's texels.
  if (gl_FragCoord.x < v_clip.x || gl_FragCoord.y < v_clip.y || gl_FragCoord.x > v_clip.z || gl_FragCoord.y > v_clip.w)
    discard;
  out_color = vec4(u_mode == 0 ? c.rgb : vec3(0.0), 1.0);
  out_value = v_value;
}
