// Image pass of the analytic program: Buffer A (iChannel0 by default) as this frame left it,
// divided by the number of frames so far, so that after N frames the Image pass shows
// (1, x, y, (N - 1) / 2) at pixel centre (x, y). Seeing the previous frame's Buffer A
// instead would show (N - 1) / N in red.
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    vec4 accumulated = texelFetch(iChannel0, ivec2(fragCoord), 0);
    fragColor = accumulated / float(iFrame + 1);
}
