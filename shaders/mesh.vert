#version 330 core
// The scene mesh: one vertex per face corner with the face's own normal (flat shading).
layout(location = 0) in vec3 aPosition;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec3 aColour;
layout(location = 3) in float aEmissive;
uniform mat4 uViewProjection;
out vec3 vPosition;
out vec3 vNormal;
out vec3 vColour;
out float vEmissive;
void main() {
    vPosition = aPosition;
    vNormal = aNormal;
    vColour = aColour;
    vEmissive = aEmissive;
    gl_Position = uViewProjection * vec4(aPosition, 1.0);
}
