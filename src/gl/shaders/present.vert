#version 430 core
// The viewer's present pass (src/gl/present.cpp): one triangle that covers the
// whole viewport, made from gl_VertexID alone (no vertex buffer).
void main() {
    // Vertices (-1,-1), (3,-1), (-1,3): the clip square lies inside.
    const vec2 p = vec2(float((gl_VertexID & 1) * 4 - 1), float((gl_VertexID >> 1) * 4 - 1));
    gl_Position = vec4(p, 0.0, 1.0);
}
