// An Image pass that writes where it is, as a fraction of the image (fragCoord / iResolution.xy),
// and the size of its iChannel0 (Buffer A by default): at --width 6 --height 3 the pixel at
// column x, row y (from the bottom) is ((x + 0.5) / 6, (y + 0.5) / 3, 6, 3).
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    fragColor = vec4(fragCoord / iResolution.xy, iChannelResolution[0].xy);
}
