#version 330 core
// Debug overlays (point marker, normal, path edges, light fragments): coloured primitives.
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec4 aColour;
uniform mat4 uViewProjection;
// Each vertex moved toward the eye by uPull of its distance (the lines drawn in the light's
// plane, so that they win the depth test against the light itself; 0 for everything else).
uniform vec3 uEye;
uniform float uPull;
out vec4 vColour;
void main() {
    vColour = aColour;
    gl_Position = uViewProjection * vec4(mix(aPosition, uEye, uPull), 1.0);
}
