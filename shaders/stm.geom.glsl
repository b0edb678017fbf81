#version 450 core
// Mesh pass of render_stm: chooses each triangle's segment with the rule of assign_faces
// (libstm/segments.cpp; keep them in step): candidates are the segments incident to the nodes of
// the triangle's vertices (all segments when there are none); among those over which the centroid
// lies (axial parameter in [0, 1]) the one whose axis is most perpendicular to the face normal
// wins, otherwise the one nearest to the centroid; ties go to the corners' distance, then to the
// lower index. It also picks the angle the fragment shader unwraps phi against (the centroid's).
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

in vec3 vg_position[];
in vec3 vg_view_position[];
in vec3 vg_normal[];
flat in int vg_node[];

uniform samplerBuffer u_segments;  // 6 texels per segment, see render_stm.cpp
uniform isamplerBuffer u_nodes;    // node n's segments: entries [offset(n), offset(n + 1)), offsets first
uniform int u_segment_count;
uniform bool u_flat;

out vec3 v_position;
out vec3 v_view_position;
out vec3 v_normal;
flat out int v_segment;
flat out float v_phi_ref;
flat out int v_face;

const float kTol = 1e-5;  // float counterpart of assign_faces' 1e-9 tie tolerance

float distance_to_segment(vec3 p, vec3 a, vec3 b, out float t) {
  vec3 ab = b - a;
  float l2 = dot(ab, ab);
  t = l2 > 0.0 ? dot(p - a, ab) / l2 : 0.0;
  return length(p - (a + clamp(t, 0.0, 1.0) * ab));
}

int best_over = -1, best_near = -1;
float over_cos = 0.0, over_dist = 0.0, near_dist = 0.0, near_cos = 0.0, near_corners = 0.0;

void consider(int e, vec3 c, vec3 n, float nn) {
  vec3 a = texelFetch(u_segments, 6 * e).xyz;
  vec3 b = texelFetch(u_segments, 6 * e + 1).xyz;
  float t, tk;
  float dist = distance_to_segment(c, a, b, t);
  float len = length(b - a);
  float cs = len > 0.0 && nn > 0.0 ? abs(dot(n, b - a)) / len : 1.0;
  float corners = distance_to_segment(vg_position[0], a, b, tk) + distance_to_segment(vg_position[1], a, b, tk) +
                  distance_to_segment(vg_position[2], a, b, tk);
  float dtol = kTol * (dist + len), ctol = kTol * (corners + len);
  if (len > 0.0 && nn > 0.0 && t >= -kTol && t <= 1.0 + kTol) {
    bool better = best_over < 0 || cs < over_cos - kTol ||
                  (cs <= over_cos + kTol && (corners < over_dist - ctol || (corners <= over_dist + ctol && e < best_over)));
    if (better) best_over = e, over_cos = cs, over_dist = corners;
  }
  bool better = best_near < 0 || dist < near_dist - dtol ||
                (dist <= near_dist + dtol &&
                 (cs < near_cos - kTol ||
                  (cs <= near_cos + kTol && (corners < near_corners - ctol || (corners <= near_corners + ctol && e < best_near)))));
  if (better) best_near = e, near_dist = dist, near_cos = cs, near_corners = corners;
}

void main() {
  vec3 c = (vg_position[0] + vg_position[1] + vg_position[2]) / 3.0;
  vec3 n = cross(vg_position[1] - vg_position[0], vg_position[2] - vg_position[0]);
  float nn = length(n);
  if (nn > 0.0) n /= nn;
  int candidates = 0;
  for (int k = 0; k < 3; ++k) {
    int node = vg_node[k];
    int end = texelFetch(u_nodes, node + 1).x;
    for (int i = texelFetch(u_nodes, node).x; i < end; ++i, ++candidates) consider(texelFetch(u_nodes, i).x, c, n, nn);
  }
  if (candidates == 0)
    for (int e = 0; e < u_segment_count; ++e) consider(e, c, n, nn);
  int s = best_over >= 0 ? best_over : best_near;

  // Reference angle: the centroid's, or a corner's when the centroid lies on the axis.
  vec3 a = texelFetch(u_segments, 6 * s).xyz;
  vec3 e1 = texelFetch(u_segments, 6 * s + 2).xyz;
  vec3 e2 = texelFetch(u_segments, 6 * s + 3).xyz;
  vec3 q = c - a;
  if (length(vec2(dot(q, e1), dot(q, e2))) < 1e-6 * max(length(q), 1e-30)) q = vg_position[0] - a;
  float phi_ref = atan(dot(q, e2), dot(q, e1));

  vec3 face_normal = normalize(cross(vg_view_position[1] - vg_view_position[0], vg_view_position[2] - vg_view_position[0]));
  for (int k = 0; k < 3; ++k) {
    v_position = vg_position[k];
    v_view_position = vg_view_position[k];
    v_normal = u_flat ? face_normal : vg_normal[k];
    v_segment = s;
    v_phi_ref = phi_ref;
    v_face = gl_PrimitiveIDIn;
    gl_Position = gl_in[k].gl_Position;
    EmitVertex();
  }
  EndPrimitive();
}
