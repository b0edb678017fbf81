#version 450 core
// Mesh pass of render_stm: positions only (relative to the framing centre), a normal for
// shading, the skeleton node of the vertex (layout.skeleton.vertex_node) and the orientation of
// its part (face_orientation), for the geometry shader's choice of segment; no uv.
layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in int in_node;
layout(location = 3) in int in_orient;  // face_orientation of the vertex's part

uniform mat4 u_model_view;
uniform mat4 u_projection;

out vec3 vg_position;  // model space, relative to the framing centre
out vec3 vg_view_position;
out vec3 vg_normal;
flat out int vg_node;
flat out int vg_orient;

void main() {
  vec4 p = u_model_view * vec4(in_position, 1.0);
  vg_position = in_position;
  vg_view_position = p.xyz;
  vg_normal = mat3(u_model_view) * in_normal;
  vg_node = in_node;
  vg_orient = in_orient;
  gl_Position = u_projection * p;
}
