// The asset library's materials (phav_generator.world.materials.Material), computed from the
// surface's position in its mesh's own frame (v_uv carries it): integer hashes only, so the
// same surface point gets the same value on every CPU and as it moves.
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

// A value in [0, 1) per cell of 1/scale metres.
float cell_noise(vec3 p, float scale) {
    return float(hash_u(ivec3(floor(p * scale)))) * (1.0 / 4294967296.0);
}

// Albedo (linear) and gloss (x: reflectance at normal incidence, y: how much of the
// environment the surface reflects) of material `pattern` at object position p.
vec3 material(int pattern, vec3 p, vec3 c, out vec2 gloss) {
    gloss = vec2(0.0);
    if (pattern == 5) {  // painted metal: a clear coat over the paint
        gloss = vec2(0.12, 0.6);
        return c * (0.97 + 0.06 * cell_noise(p, 60.0));
    }
    if (pattern == 6) {  // glass
        gloss = vec2(0.06, 1.0);
        return c;
    }
    if (pattern == 7) {  // chrome
        gloss = vec2(0.55, 0.9);
        return c * 0.6;
    }
    if (pattern == 8) return c * (0.85 + 0.3 * cell_noise(p, 150.0));  // rubber
    if (pattern == 9) {  // wood: grain across the planks, knots of darker cells
        float grain = fract(dot(p, vec3(0.7, 9.0, 13.0)) + 0.35 * cell_noise(vec3(p.x * 0.25, p.y, p.z), 30.0));
        gloss = vec2(0.03, 0.15);
        return c * (0.80 + 0.22 * grain) * (0.94 + 0.12 * cell_noise(p, 8.0));
    }
    if (pattern == 10) return c * (0.86 + 0.14 * cell_noise(p, 120.0)) * (0.95 + 0.1 * cell_noise(p, 6.0));  // fabric
    if (pattern == 11) {  // leather
        gloss = vec2(0.04, 0.25);
        return c * (0.90 + 0.16 * cell_noise(p, 35.0));
    }
    if (pattern == 12) {  // plastic
        gloss = vec2(0.04, 0.25);
        return c * (0.96 + 0.08 * cell_noise(p, 120.0));
    }
    if (pattern == 13) return c * (0.84 + 0.16 * cell_noise(p, 25.0)) * (0.9 + 0.2 * cell_noise(p, 180.0));  // concrete
    if (pattern == 14) {  // metal: vertical streaks
        gloss = vec2(0.2, 0.35);
        return c * (0.90 + 0.18 * cell_noise(vec3(p.x, p.y, p.z * 0.05), 80.0));
    }
    return c;
}
