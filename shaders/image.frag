#version 330 core
in vec2 vTexCoord;
uniform sampler2D uImage;
out vec4 fragColour;
void main() { fragColour = vec4(texture(uImage, vTexCoord).rgb, 1.0); }
