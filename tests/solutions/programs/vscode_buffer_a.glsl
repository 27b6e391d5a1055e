// Buffer A: red the frame number plus one, green Buffer B's red of the previous frame.
#include "vscode_common.glsl"
#iChannel0 "self"
#iChannel1 "file://vscode_buffer_b.glsl"
#iKeyboard
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    fragColor = vec4(FRAME_VALUE(iFrame), fetch(iChannel1, fragCoord).r, 0.0, 1.0);
}
