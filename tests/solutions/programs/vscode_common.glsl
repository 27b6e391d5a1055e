// Common tab of the chain program written as VS Code Shader Toy tabs (the other vscode_*
// files include it and wire their channels with #iChannelN directives, no --channel).
#define FRAME_VALUE(frame) float((frame) + 1)
vec4 fetch(sampler2D channel, vec2 frag_coord) {
    return texelFetch(channel, ivec2(frag_coord), 0);
}
