// Buffer A with a loop that never ends (its bound is never reached): vkpath shadertoy must stop
// with one error line naming this file and the pass, not hang and not write an image (on
// lavapipe the driver would otherwise end the loop silently and the image would be wrong).
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    float sum = 0.0;
    for (int i = 0; i < 1; i *= 1) {
        sum += 1.0;
    }
    fragColor = vec4(sum);
}
