// Common tab of a program whose two passes both define a helper named `shade` (with other
// bodies), which ShaderToy allows: it compiles each pass on its own after the Common tab.
float base_value() {
    return 1.0;
}
