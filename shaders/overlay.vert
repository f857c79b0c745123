#version 330 core
// Debug overlays (point marker, normal, path edges, light fragments): coloured primitives.
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec4 aColour;
uniform mat4 uViewProjection;
out vec4 vColour;
void main() {
    vColour = aColour;
    gl_Position = uViewProjection * vec4(aPosition, 1.0);
}
