#version 330 core
// Flat shading for orientation only (not the lighting solution): a headlight at the eye, both
// sides lit, the back side darkened so that one-sided receivers and lights read as such. Emissive
// faces (the area lights) are drawn in their own colour, unshaded, from their front only: they
// emit to that side alone, and the renderer shows their back black, so here it is a dark grey (a
// flipped light reads as such). A textured face's colour is its material's factor times the
// texture (sRGB texels, sampled as linear), as the renderer's kd(x).
in vec3 vPosition;
in vec3 vNormal;
in vec3 vColour;
in float vEmissive;
in vec2 vUv;
uniform vec3 uEye;
uniform float uTextured;
uniform sampler2D uKd;
out vec4 fragColour;
void main() {
    vec3 toEye = normalize(uEye - vPosition);
    float c = dot(normalize(vNormal), toEye);
    if (vEmissive > 0.5) {
        fragColour = c >= 0.0 ? vec4(vColour, 1.0) : vec4(vec3(0.08), 1.0);
        return;
    }
    vec3 colour = vColour;
    if (uTextured > 0.5) colour *= texture(uKd, vUv).rgb;
    float shade = c >= 0.0 ? 0.3 + 0.7 * c : 0.15 + 0.25 * (-c);
    fragColour = vec4(colour * shade, 1.0);
}
