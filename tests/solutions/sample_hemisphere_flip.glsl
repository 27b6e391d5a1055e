// A correct sample_hemisphere written differently from the workshop's: directions below the
// hemisphere are negated (omega -> -omega) instead of mirrored at the tangent plane. The
// sphere's uniform density is symmetric under both maps, so the result is uniform too.
vec3 sample_hemisphere(vec2 random_numbers, vec3 normal) {
    vec3 direction = sample_sphere(random_numbers);
    return (dot(direction, normal) < 0.0) ? -direction : direction;
}
