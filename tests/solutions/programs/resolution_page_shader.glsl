#version 300 es
// A WebGL page shader that gets its canvas size from a uniform, as page shaders do: run as
// the Image pass, u_resolution is the render's --width and --height, and its own declaration
// of ShaderToy's iTime is dropped for vkpath's (0 at frame 0).
precision highp float;
uniform vec2 u_resolution;
uniform float iTime;
out vec4 outColor;

void main() {
    outColor = vec4(gl_FragCoord.xy / u_resolution, u_resolution.x + iTime, u_resolution.y);
}
