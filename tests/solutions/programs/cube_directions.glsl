// An Image tab that samples a cube-map channel by direction (tests/shadertoy_cli.rs): pixel
// column i writes texture(iChannel1, DIRECTIONS[i]). The first eight point at the centre of
// one texel of a 2 x 2 face (Vulkan's and OpenGL's face selection; s and t from the face
// image's top-left corner), the last six along the axes. The channel is wired as the VS Code
// Shader Toy extension wires a cube map: six faces cube_px.png … cube_nz.png beside this file.
#iChannel1 "file://cube_{}.png" // the wildcard: px, nx, py, ny, pz, nz
#iChannel1::Type "CubeMap"

const vec3 DIRECTIONS[14] = vec3[14](
    vec3(1.0, 0.5, 0.5),    // +X, s 0.25, t 0.25: its image's top-left texel
    vec3(1.0, -0.5, -0.5),  // +X, bottom-right
    vec3(-1.0, 0.5, -0.5),  // -X, top-left
    vec3(-0.5, 1.0, -0.5),  // +Y, top-left
    vec3(0.5, -1.0, -0.5),  // -Y, bottom-right
    vec3(-0.5, 0.5, 1.0),   // +Z, top-left
    vec3(0.5, 0.5, -1.0),   // -Z, top-left
    vec3(0.5, -0.5, -1.0),  // -Z, bottom-left
    vec3(1.0, 0.0, 0.0),
    vec3(-1.0, 0.0, 0.0),
    vec3(0.0, 1.0, 0.0),
    vec3(0.0, -1.0, 0.0),
    vec3(0.0, 0.0, 1.0),
    vec3(0.0, 0.0, -1.0)
);

void mainImage(out vec4 fragColor, in vec2 fragCoord) {
    fragColor = texture(iChannel1, DIRECTIONS[int(fragCoord.x)]);
}
