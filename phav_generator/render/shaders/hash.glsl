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
