// Buffer A: its own `shade` (the Image tab has another); writes 2 + base_value() = 3.
float shade() {
    return 2.0 + base_value();
}

void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    fragColor = vec4(shade());
}
