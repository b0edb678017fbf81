#version 450 core
// Mesh pass of render_mesh: positions arrive relative to the framing centre (float precision
// stays good for meshes far from the origin); model_view is a rigid motion, so it also turns normals.
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) in vec3 in_color;

uniform mat4 u_model_view;
uniform mat4 u_projection;

out vec3 v_view_position;
out vec3 v_normal;
out vec2 v_uv;
out vec3 v_color;

void main() {
  vec4 p = u_model_view * vec4(in_position, 1.0);
  v_view_position = p.xyz;
  v_normal = mat3(u_model_view) * in_normal;
  v_uv = in_uv;
  v_color = in_color;
  gl_Position = u_projection * p;
}
