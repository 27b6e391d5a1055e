// Image: A's red and green and B's red.
#include "vscode_common.glsl"
#iChannel0 "file://vscode_buffer_a.glsl"
#iChannel1 "file://vscode_buffer_b.glsl"
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    vec4 a = fetch(iChannel0, fragCoord);
    fragColor = vec4(a.r, a.g, fetch(iChannel1, fragCoord).r, 1.0);
}
