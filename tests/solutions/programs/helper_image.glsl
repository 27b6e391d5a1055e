// The Image pass: its own `shade` reads Buffer A (iChannel0) and adds 10: 13 everywhere.
float shade(vec2 frag_coord) {
    return texelFetch(iChannel0, ivec2(frag_coord), 0).r + 10.0;
}

void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    fragColor = vec4(shade(fragCoord), base_value(), 0.0, 1.0);
}
