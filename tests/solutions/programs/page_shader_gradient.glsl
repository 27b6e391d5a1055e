#version 300 es
// A WebGL page shader: main() with gl_FragCoord and an out variable, run as the Image pass.
// At width 4: red 0.125, 0.375, 0.625, 0.875 (x / 4 at pixel centres); green 0.5; blue 2.0
// (clamped to 1 in a PNG).
precision highp float;
uniform vec2 u_resolution;
out vec4 fragColor;
void main() {
    fragColor = vec4(gl_FragCoord.x / 4.0, 0.5, 2.0, 1.0);
}
