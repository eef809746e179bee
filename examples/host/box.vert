#version 450
// The example host's own object: an axis-aligned box from gl_VertexIndex (36 vertices, 12
// triangles, counter-clockwise seen from outside), in the ocean's world (z up, metres).
layout(push_constant) uniform Box {
    // The unit box [-1, 1]^3 to clip space: the world's projection and view, then the box's
    // centre and half extents (axis-aligned and positive, so the faces' normals are the axes).
    mat4 clip_from_box;
} box;
layout(location = 0) out vec3 out_normal;

const vec3 NORMALS[6] = vec3[](vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0), vec3(0, -1, 0), vec3(0, 0, 1), vec3(0, 0, -1));

void main() {
    int face = gl_VertexIndex / 6;
    int corner = gl_VertexIndex % 6;
    // Two triangles over the face's square: (0,0) (1,0) (1,1) and (0,0) (1,1) (0,1).
    vec2 st = vec2[](vec2(0, 0), vec2(1, 0), vec2(1, 1), vec2(0, 0), vec2(1, 1), vec2(0, 1))[corner] * 2.0 - 1.0;
    vec3 n = NORMALS[face];
    // Two axes across the face with u x v = n, so the winding faces out.
    vec3 u = abs(n.z) > 0.5 ? vec3(1, 0, 0) : vec3(0, 0, 1);
    u = normalize(cross(u, n));
    vec3 v = cross(n, u);
    gl_Position = box.clip_from_box * vec4(n + st.x * u + st.y * v, 1.0);
    out_normal = n;
}
