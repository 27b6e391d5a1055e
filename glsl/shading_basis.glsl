// The one shading basis: an orthonormal frame (tangent, bitangent, normal) around a unit
// normal, in which the BSDFs and the cosine sampler work. Its users: glsl/brdf.glsl (the GGX
// and diffuse lobes), glsl/layered_bsdf.glsl (the layers) and
// glsl/importance_sampling.glsl (sample_hemisphere_cosine()).
// Rust twin: src/cpu/shading_basis.rs.
#ifndef VKPATH_SHADING_BASIS_GLSL
#define VKPATH_SHADING_BASIS_GLSL

// An orthonormal basis (tangent, bitangent, normal) around a unit normal (Duff et al. 2017,
// "Building an Orthonormal Basis, Revisited", JCGT 6(1)); the BSDFs are isotropic, so any
// tangent serves. Multiply a local vector by it to get the world vector; a world vector
// times it (vector * basis) is the local vector.
// \param normal Unit normal, world space
// \return Columns tangent, bitangent, normal: unit, orthogonal, right-handed
mat3 get_shading_basis(vec3 normal) {
    // sign_z keeps a = -1 / (sign_z + n_z) away from a division by zero at n_z = -1.
    float sign_z = (normal.z >= 0.0) ? 1.0 : -1.0;
    float a = -1.0 / (sign_z + normal.z);
    float b = normal.x * normal.y * a;
    vec3 tangent = vec3(1.0 + sign_z * normal.x * normal.x * a, sign_z * b, -sign_z * normal.x);
    vec3 bitangent = vec3(b, sign_z + normal.y * normal.y * a, -normal.y);
    return mat3(tangent, bitangent, normal);
}

#endif
