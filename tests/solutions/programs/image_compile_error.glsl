// An Image pass with an error on line 4: the message must name this file and that line.
void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    vec3 colour = vec3(fragCoord, 0.0);
    fragColor = vec4(colour, undefined_alpha);
}
