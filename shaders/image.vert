#version 330 core
// The rendered view: bands of the renderer's image drawn over the 3D view, pixel for pixel.
layout(location = 0) in vec2 aPosition;  // clip space of the view
layout(location = 1) in vec2 aTexCoord;  // rows from the top: v = 0 is the image's first row
out vec2 vTexCoord;
void main() {
    vTexCoord = aTexCoord;
    gl_Position = vec4(aPosition, 0.0, 1.0);
}
