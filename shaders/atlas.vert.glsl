#version 450 core
// Atlas pass of render_atlas: a triangle is drawn at its STM texel coordinates (capsule mapping
// of its segment, computed on the CPU), carrying any per-corner attribute to interpolate.
layout(location = 0) in vec3 in_atlas;  // texel x, texel y, depth (own faces in front of neighbours)
layout(location = 1) in vec4 in_clip;   // texel rectangle (x0, y0, x1, y1) this triangle may fill
layout(location = 2) in vec4 in_value;  // attribute: source uv in xy, or float values

uniform float u_size;  // atlas width = height in texels

flat out vec4 v_clip;
out vec4 v_value;

void main() {
  v_clip = in_clip;
  v_value = in_value;
  gl_Position = vec4(in_atlas.xy / u_size * 2.0 - 1.0, in_atlas.z * 2.0 - 1.0, 1.0);
}
