// Buffer A of tests/shadertoy_cli.rs: red iFrame + 1 every frame, green the sum of four calls
// of a helper, but its texels are discarded as ShaderToy programs do: the left half from
// frame 3 on (in the helper, which returns a value, inside a loop) and the bottom row from
// frame 4 on (in mainImage). A discarded texel is not written, so it keeps what its target
// held; ShaderToy renders a buffer into one of two targets in turn, so that is the value of
// two frames before. After 6 frames (0-5, the last into the target of frames 1 and 3):
// right half, top row (6, 4, 0, 1); right half, bottom row (4, 4, 0, 1); left half (2, 4, 0, 1).
float counted_unless_discarded(vec2 fragCoord) {
    if (iFrame >= 3 && fragCoord.x < 0.5 * iResolution.x)
        discard;
    return 1.0;
}

void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    float calls = 0.0;
    for (int i = 0; i < 4; i++)
        calls += counted_unless_discarded(fragCoord);
    if (fragCoord.y < 1.0 && iFrame >= 4) discard; else fragColor = vec4(0.0);
    fragColor = vec4(float(iFrame + 1), calls, 0.0, 1.0);
}
