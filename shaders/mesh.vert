#version 330 core
// The scene mesh: one vertex per face corner with the face's own normal (flat shading), and the
// corner's texture coordinates (transformed already; zero on untextured faces).
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec3 aColour;
layout(location = 3) in float aEmissive;
layout(location = 4) in vec2 aUv;
uniform mat4 uViewProjection;
out vec3 vPosition;
out vec3 vNormal;
out vec3 vColour;
out float vEmissive;
out vec2 vUv;
void main() {
    vPosition = aPosition;
    vNormal = aNormal;
    vColour = aColour;
    vEmissive = aEmissive;
    vUv = aUv;
    gl_Position = uViewProjection * vec4(aPosition, 1.0);
}
