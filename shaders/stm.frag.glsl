#version 450 core
// Mesh pass of render_stm: STM coordinates per fragment from the interpolated position, with the
// capsule mapping of libstm/capsule_uv.cpp (same formula, keep them in step), and trilinear
// sampling of the atlas with derivatives of an angle unwrapped against a per-triangle reference,
// so that a triangle across phi = 0 selects the same mip level as its neighbours (no seam line).
in vec3 v_position;
in vec3 v_view_position;
in vec3 v_normal;
flat in int v_segment;
flat in float v_phi_ref;
flat in int v_face;

uniform samplerBuffer u_segments;
uniform sampler2D u_atlas;
uniform float u_size;  // atlas texels
uniform bool u_lit;
uniform bool u_orthographic;
uniform float u_ambient;
uniform int u_output;  // float target: 0 nothing, 1 (atlas x, atlas y, segment, face), 2 (position, 1)

layout(location = 0) out vec4 out_color;
layout(location = 1) out vec4 out_value;

const float kPi = 3.14159265358979;

// capsule_uv: returns (u, v, phi, rho) for the rectangle (w along the axis, h around it, caps d).
vec4 capsule_uv(vec3 a, vec3 b, vec3 e1, vec3 e2, float w, float h, float d, vec3 p) {
  vec3 ab = b - a;
  float len = length(ab);
  vec3 axis = len > 0.0 ? ab / len : cross(e1, e2);
  vec3 x = p - a;
  float t = len > 0.0 ? dot(x, axis) / len : 0.0;
  float px = dot(x, e1), py = dot(x, e2);
  float rho = length(vec2(px, py));
  float phi = rho > 0.0 ? atan(py, px) : 0.0;
  if (phi < 0.0) phi += 2.0 * kPi;
  if (phi >= 2.0 * kPi) phi = 0.0;
  float u = h * phi / (2.0 * kPi);
  float quarter = kPi / 2.0;
  float v;
  if (t < 0.0) {
    float theta = atan(-dot(x, axis), rho);
    v = d * (1.0 - theta / quarter);
  } else if (t > 1.0) {
    float theta = atan(dot(p - b, axis), rho);
    v = w - d + d * theta / quarter;
  } else {
    v = d + t * (w - 2.0 * d);
  }
  return vec4(u, v, phi, rho);
}

vec2 local_to_atlas(vec4 rect, bool rotated, float u, float v) {
  return rotated ? vec2(rect.x + u, rect.y + v) : vec2(rect.x + v, rect.y + u);
}

void main() {
  int s = v_segment;
  vec3 a = texelFetch(u_segments, 6 * s).xyz;
  vec3 b = texelFetch(u_segments, 6 * s + 1).xyz;
  vec4 e1 = texelFetch(u_segments, 6 * s + 2);  // e1, extension past a in radii
  vec4 e2 = texelFetch(u_segments, 6 * s + 3);  // e2, extension past b in radii
  vec4 rect = texelFetch(u_segments, 6 * s + 4);  // x, y, w, h
  vec4 extra = texelFetch(u_segments, 6 * s + 5);  // d, rotated, radius
  // capsule_frame: the ends moved out along the axis by the extensions.
  float len = length(b - a);
  vec3 axis = len > 0.0 ? (b - a) / len : vec3(0.0);
  vec3 a_end = a - e1.w * extra.z * axis, b_end = b + e2.w * extra.z * axis;
  bool rotated = extra.y > 0.5;
  vec4 c = capsule_uv(a_end, b_end, e1.xyz, e2.xyz, rect.z, rect.w, extra.x, v_position);
  vec2 atlas = local_to_atlas(rect, rotated, c.x, c.y);
  // The same point with phi continued from the triangle's reference angle: smooth across phi = 0.
  float dphi = c.z - v_phi_ref;
  dphi -= 2.0 * kPi * floor(dphi / (2.0 * kPi) + 0.5);
  vec2 unwrapped = local_to_atlas(rect, rotated, rect.w * (v_phi_ref + dphi) / (2.0 * kPi), c.y);
  vec2 ddx = dFdx(unwrapped) / u_size, ddy = dFdy(unwrapped) / u_size;
  vec3 color = textureGrad(u_atlas, atlas / u_size, ddx, ddy).rgb;
  if (u_lit) {
    vec3 n = normalize(v_normal);
    vec3 l = u_orthographic ? vec3(0.0, 0.0, 1.0) : normalize(-v_view_position);
    color *= u_ambient + (1.0 - u_ambient) * abs(dot(n, l));
  }
  out_color = vec4(color, 1.0);
  out_value = u_output == 1 ? vec4(atlas, float(s), float(v_face)) : u_output == 2 ? vec4(v_position, 1.0) : vec4(0.0);
}
