// A single file as the VS Code Shader Toy extension runs it (tests/shadertoy_cli.rs): a page
// shader (void main(), gl_FragCoord, gl_FragColor) that reads its own previous frame through
// #iChannel0 "self" and keeps the running mean of one value per frame: red x + iFrame (x the
// pixel centre's), green iFrame squared. After N frames: red x + (N - 1) / 2, green
// (N - 1)(2N - 1) / 6, blue and alpha 1. Pressing R restarts the mean (#iKeyboard; no key
// is ever down in a headless run).
#iChannel0 "self"
#iKeyboard

void main() {
    vec4 previous = texture(iChannel0, gl_FragCoord.xy / iResolution.xy);
    vec4 value = vec4(gl_FragCoord.x + float(iFrame), float(iFrame * iFrame), 1.0, 1.0);
    gl_FragColor = previous + (value - previous) / float(iFrame + 1);
    if (isKeyPressed(Key_R))
        gl_FragColor = value;
}
