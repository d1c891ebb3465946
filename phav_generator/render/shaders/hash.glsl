// An integer hash of a lattice cell: the same bits on every CPU and driver (no float
// transcendental), for the noise of the materials and the clouds.
uint hash_u(ivec3 c) {
    uvec3 v = uvec3(c + 65536);
    uint h = (v.x * 1597334677u) ^ (v.y * 3812015801u) ^ (v.z * 2798796415u);
    h ^= h >> 15;
    h *= 2246822519u;
    h ^= h >> 13;
    h *= 3266489917u;
    h ^= h >> 16;
    return h;
}

// Smooth value noise in [0, 1) over a plane: the cells' hashed values blended across each
// unit cell (four hashes, half the cost of the 3D kind, for surfaces that lie flat).
float value_noise2(vec2 p) {
    vec2 i = floor(p);
    vec2 f = p - i;
    f = f * f * (3.0 - 2.0 * f);
    float v = 0.0;
    for (int k = 0; k < 4; ++k) {
        vec2 o = vec2(k & 1, k >> 1);
        vec2 w = mix(1.0 - f, f, o);
        v += w.x * w.y * float(hash_u(ivec3(i + o, 0))) * (1.0 / 4294967296.0);
    }
    return v;
}
