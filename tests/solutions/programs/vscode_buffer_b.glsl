// Buffer B: sums Buffer A's red over the frames.
#include "vscode_common.glsl"
#iChannel0 "self"
#iChannel1 "file://vscode_buffer_a.glsl"
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    fragColor = vec4(fetch(iChannel0, fragCoord).r + fetch(iChannel1, fragCoord).r, 0.0, 0.0, 1.0);
}
