// Buffer B of the two-buffer program: sums Buffer A's red over the frames (iChannel0 is B's
// own previous frame, iChannel1 = buffer-a, which runs before B: this frame's A), so after
// N frames B's red is 1 + 2 + ... + N = N (N + 1) / 2.
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    fragColor = vec4(fetch(iChannel0, fragCoord).r + fetch(iChannel1, fragCoord).r, 0.0, 0.0, 1.0);
}
