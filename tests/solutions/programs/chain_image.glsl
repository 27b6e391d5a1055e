// Image pass of the two-buffer program: A's red and green and B's red (iChannel0 = Buffer A,
// iChannel1 = buffer-b). After N frames: (N, (N - 1) N / 2, N (N + 1) / 2, 1).
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    vec4 a = fetch(iChannel0, fragCoord);
    fragColor = vec4(a.r, a.g, fetch(iChannel1, fragCoord).r, 1.0);
}
