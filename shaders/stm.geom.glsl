#version 450 core
// Mesh pass of render_stm: chooses each triangle's segment with the rule of assign_faces
// (libstm/layout/segments.cpp) given the layout's radii (assign_faces_with_radii).
// distance_to_segment, face_stretch, rate_candidate, better_candidate, second_pass_cost and
// better_second below mirror the C++ functions of the same names line by line, in float: keep them
// in step. First pass: the segments incident to the nodes of the triangle's vertices (all segments
// when there are none), visited in increasing index like the C++ (the order decides exact ties).
// Second pass: a face the first pass's segment folds or stretches by 2 or more at the segment's
// radius tries the segments at nodes within two skeleton edges (ties to the lower index, so the
// order of the visits does not matter).
// The pass also picks the angle the fragment shader unwraps phi against (the centroid's).
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

in vec3 vg_position[];
in vec3 vg_view_position[];
in vec3 vg_normal[];
flat in int vg_node[];
flat in int vg_orient[];  // face_orientation: +1, or -1 for a part wound inside out

uniform samplerBuffer u_segments;  // 6 texels per segment, see render_stm.cpp
uniform isamplerBuffer u_nodes;    // node n's segments: entries [offset(n), offset(n + 1)), offsets first
uniform int u_segment_count;
uniform bool u_flat;
uniform bool u_second_pass;  // Layout::assignment >= 2

out vec3 v_position;
out vec3 v_view_position;
out vec3 v_normal;
flat out int v_segment;
flat out float v_phi_ref;
flat out int v_face;

const float kPi = 3.14159265358979;
const float kGoodStretch = 2.0;  // as in segments.cpp
// Float counterparts of the C++ tolerances: ties (1e-9 there), a corner on the axis (1e-9) and a
// face mapped flat (1e-12). kTol sits just above float noise: at 1e-5, two Spot faces whose
// normal scores differ by 9e-6 became ties here and went to the nearer segment, unlike on the CPU.
const float kTol = 2e-6;
const float kAxisEps = 1e-6;
const float kFlatEps = 1e-6;
const float kInf = 3.0e38;  // stands for the C++ infinity (compared explicitly, never computed with)

float distance_to_segment(vec3 p, vec3 a, vec3 b) {
  vec3 ab = b - a;
  float l2 = dot(ab, ab);
  float tt = l2 > 0.0 ? dot(p - a, ab) / l2 : 0.0;
  float c = clamp(tt, 0.0, 1.0);
  return length(p - (a + c * ab));
}

float face_stretch(vec3 p[3], float orient, vec3 a, vec3 b, float radius, out bool folded) {
  folded = false;
  vec3 ab = b - a;
  float len = length(ab);
  if (!(len > 0.0)) return kInf;
  vec3 axis = ab / len;
  vec3 e1 = abs(axis.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0);
  e1 = normalize(e1 - axis * dot(axis, e1));
  vec3 e2 = cross(axis, e1);
  float r = 0.0;
  for (int k = 0; k < 3; ++k) r += distance_to_segment(p[k], a, b) / 3.0;
  if (radius > 0.0) r = radius;
  if (!(r > 0.0)) return kInf;
  float phi[3], v[3], rho[3];
  for (int k = 0; k < 3; ++k) {
    vec3 x = p[k] - a;
    float t = dot(x, axis) / len;
    rho[k] = length(vec2(dot(x, e1), dot(x, e2)));
    phi[k] = rho[k] > 0.0 ? atan(dot(x, e2), dot(x, e1)) : 0.0;  // atan(0, 0) is undefined in GLSL
    if (t < 0.0) v[k] = -r * atan(-dot(x, axis), rho[k]);
    else if (t > 1.0) v[k] = len + r * atan(dot(p[k] - b, axis), rho[k]);
    else v[k] = t * len;
  }
  float eps = kAxisEps * (r + len);
  int ref = -1;
  for (int k = 0; k < 3 && ref < 0; ++k)
    if (rho[k] > eps) ref = k;
  if (ref < 0) return kInf;
  float mean = 0.0;
  int cnt = 0;
  for (int k = 0; k < 3; ++k)
    if (rho[k] > eps) {
      float d = phi[k] - phi[ref];
      phi[k] = phi[ref] + (d - 2.0 * kPi * roundEven(d / (2.0 * kPi)));  // std::remainder
      mean += phi[k], ++cnt;
    }
  for (int k = 0; k < 3; ++k)
    if (rho[k] <= eps) phi[k] = mean / float(cnt);
  vec2 s0 = vec2(r * phi[0], v[0]), s1 = vec2(r * phi[1], v[1]), s2 = vec2(r * phi[2], v[2]);
  float a2 = orient * 0.5 * ((s1 - s0).x * (s2 - s0).y - (s2 - s0).x * (s1 - s0).y);
  float a3 = 0.5 * length(cross(p[1] - p[0], p[2] - p[0]));
  folded = a2 < 0.0;
  if (!(abs(a2) > kFlatEps * a3)) return kInf;
  vec3 Ss = (p[0] * (s1.y - s2.y) + p[1] * (s2.y - s0.y) + p[2] * (s0.y - s1.y)) / (2.0 * a2);
  vec3 St = (p[0] * (s2.x - s1.x) + p[1] * (s0.x - s2.x) + p[2] * (s1.x - s0.x)) / (2.0 * a2);
  return sqrt(0.5 * (dot(Ss, Ss) + dot(St, St)));
}

struct Candidate {
  int rank;
  float stretch;
  float score;
  float dist;
  float len;
};

Candidate rate_candidate(vec3 p[3], float orient, vec3 a, vec3 b) {
  Candidate x = Candidate(0, 0.0, 0.0, 0.0, 0.0);
  vec3 c = (p[0] + p[1] + p[2]) / 3.0;
  vec3 n = cross(p[1] - p[0], p[2] - p[0]);
  if (length(n) > 0.0) n = normalize(n);
  n *= orient;
  bool folded = false;
  x.stretch = face_stretch(p, orient, a, b, 0.0, folded);
  x.rank = folded ? 2 : x.stretch < kGoodStretch ? 0 : 1;
  vec3 ab = b - a;
  float l2 = dot(ab, ab);
  for (int k = 0; k < 4; ++k) {
    vec3 q = k < 3 ? p[k] : c;
    float t = l2 > 0.0 ? clamp(dot(q - a, ab) / l2, 0.0, 1.0) : 0.0;
    vec3 r = q - (a + t * ab);
    float rn = length(r);
    if (rn > 0.0) x.score += dot(n, r) / rn;
  }
  x.score /= 4.0;
  x.dist = distance_to_segment(c, a, b);
  x.len = sqrt(l2);
  return x;
}

bool better_candidate(Candidate x, Candidate best) {
  if (x.rank != best.rank) return x.rank < best.rank;
  if (x.rank == 0 && abs(x.score - best.score) > kTol) return x.score > best.score;
  if (x.rank > 0) {
    bool x_inf = x.stretch >= kInf, best_inf = best.stretch >= kInf;
    if (x_inf != best_inf) return best_inf;
    if (!x_inf && abs(x.stretch - best.stretch) > kTol * best.stretch) return x.stretch < best.stretch;
  }
  return x.dist < best.dist - kTol * (x.dist + x.len);
}

// The smallest segment index above prev incident to a corner's node; -1 when there is none. Going
// through the candidates this way visits them sorted and once each, like assign_faces' list.
int next_candidate(int prev) {
  int next = -1;
  for (int k = 0; k < 3; ++k) {
    int node = vg_node[k];
    int end = texelFetch(u_nodes, node + 1).x;
    for (int i = texelFetch(u_nodes, node).x; i < end; ++i) {
      int e = texelFetch(u_nodes, i).x;
      if (e > prev && (next < 0 || e < next)) next = e;
    }
  }
  return next;
}

int best = -1;
Candidate best_fit;

void consider(int e, vec3 p[3], float orient) {
  Candidate x = rate_candidate(p, orient, texelFetch(u_segments, 6 * e).xyz, texelFetch(u_segments, 6 * e + 1).xyz);
  if (best < 0 || better_candidate(x, best_fit)) best = e, best_fit = x;
}

// The capsule runs on past its nodes by its extensions (texels 2 and 3, .w), in radii.
float second_pass_cost(vec3 p[3], float orient, int e, out bool folded) {
  vec3 a = texelFetch(u_segments, 6 * e).xyz, b = texelFetch(u_segments, 6 * e + 1).xyz;
  float radius = texelFetch(u_segments, 6 * e + 5).z;
  float len = length(b - a);
  vec3 axis = len > 0.0 ? (b - a) / len : vec3(0.0);
  float s = face_stretch(p, orient, a - texelFetch(u_segments, 6 * e + 2).w * radius * axis,
                         b + texelFetch(u_segments, 6 * e + 3).w * radius * axis, radius, folded);
  return folded && s < kInf ? 2.0 * s : s;
}

bool better_second(float x, int e, float bx, int be) {
  bool xi = x >= kInf, bi = bx >= kInf;
  if (xi || bi) return xi && bi ? e < be : bi;
  if (abs(x - bx) <= kTol * bx) return e < be;
  return x < bx;
}

float best_cost;

void reconsider(int e, vec3 p[3], float orient) {
  bool folded;
  float c = second_pass_cost(p, orient, e, folded);
  if (better_second(c, e, best_cost, best)) best = e, best_cost = c;
}

int other_node(int e, int n) {
  int a = int(texelFetch(u_segments, 6 * e).w), b = int(texelFetch(u_segments, 6 * e + 1).w);
  return a == n ? b : a;
}

void second_pass(vec3 p[3], float orient) {
  bool folded;
  best_cost = second_pass_cost(p, orient, best, folded);
  if (!folded && best_cost < kGoodStretch) return;
  for (int k = 0; k < 3; ++k) {
    int n0 = vg_node[k];
    for (int i = texelFetch(u_nodes, n0).x; i < texelFetch(u_nodes, n0 + 1).x; ++i) {
      int e1 = texelFetch(u_nodes, i).x;
      reconsider(e1, p, orient);
      int n1 = other_node(e1, n0);
      for (int j = texelFetch(u_nodes, n1).x; j < texelFetch(u_nodes, n1 + 1).x; ++j) {
        int e2 = texelFetch(u_nodes, j).x;
        reconsider(e2, p, orient);
        int n2 = other_node(e2, n1);
        for (int l = texelFetch(u_nodes, n2).x; l < texelFetch(u_nodes, n2 + 1).x; ++l)
          reconsider(texelFetch(u_nodes, l).x, p, orient);
      }
    }
  }
}

void main() {
  vec3 p[3] = vec3[3](vg_position[0], vg_position[1], vg_position[2]);
  // One part, one orientation: the corners agree, so the first one's will do.
  float orient = vg_orient[0] < 0 ? -1.0 : 1.0;
  int e = next_candidate(-1);
  if (e < 0)  // nodes without edges: any segment may take the face
    for (int i = 0; i < u_segment_count; ++i) consider(i, p, orient);
  for (; e >= 0; e = next_candidate(e)) consider(e, p, orient);
  if (u_second_pass) second_pass(p, orient);
  int s = best;

  // Reference angle: the centroid's, or a corner's when the centroid lies on the axis.
  vec3 c = (p[0] + p[1] + p[2]) / 3.0;
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
