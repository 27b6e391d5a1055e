// An Image tab that shows Buffer A (iChannel0 by default) as it is: with the workshop's
// Buffer A tab (exercise7_tab.glsl) a two-tab program, as the workshop's ShaderToy has it.
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    fragColor = vec4(texelFetch(iChannel0, ivec2(fragCoord), 0).rgb, 1.0);
}
