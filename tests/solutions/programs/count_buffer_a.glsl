// Buffer A of an analytic program (tests/shadertoy_cli.rs): every frame adds
// (1, fragCoord.x, fragCoord.y, iTime * 60) to what this buffer held the frame before
// (iChannel0, its own previous frame by default, read with texture() at the pixel centre).
// After N frames: (N, N x, N y, 0 + 1 + ... + (N - 1)), exactly, at pixel centre (x, y).
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    vec4 previous = texture(iChannel0, fragCoord / iResolution.xy);
    fragColor = previous + vec4(1.0, fragCoord, round(iTime * 60.0));
}
