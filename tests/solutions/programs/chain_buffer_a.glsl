// Buffer A of the two-buffer program: red is the frame number plus one; green copies
// Buffer B's red (iChannel1 = buffer-b), which runs after A, so A sees B's previous frame:
// after frame f, A = (f + 1, B's red after frame f - 1, 0, 1).
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    fragColor = vec4(FRAME_VALUE(iFrame), fetch(iChannel1, fragCoord).r, 0.0, 1.0);
}
