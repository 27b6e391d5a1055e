// Common tab of the two-buffer program: prepended to every pass.
#define FRAME_VALUE(frame) float((frame) + 1)
vec4 fetch(sampler2D channel, vec2 frag_coord) {
    return texelFetch(channel, ivec2(frag_coord), 0);
}
