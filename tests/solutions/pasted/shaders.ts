// A three.js material whose fragment shader holds the workshop's PCG2D (written for
// vkpath's tests, shaped like attendees' TypeScript ports).
import { ShaderMaterial } from "three";

export const pathTracerMaterial = new ShaderMaterial({
  uniforms: { u_frame: { value: 0 } },
  fragmentShader: /* glsl */ `
    precision highp float;
    uniform int u_frame;
    out vec4 fragColor;

vec2 get_random_numbers(inout uvec2 seed) {
    seed = 1664525u * seed + 1013904223u;
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    seed.x += 1664525u * seed.y;
    seed.y += 1664525u * seed.x;
    seed ^= (seed >> 16u);
    return vec2(seed) * 2.32830643654e-10;
}

    void main() {
      uvec2 seed = uvec2(gl_FragCoord.xy) ^ uvec2(u_frame << 16);
      fragColor = vec4(get_random_numbers(seed), 0.0, ${ALPHA});
    }
  `,
});
