// The asset library's materials (phav_generator.world.materials.Material), computed from the
// surface's position in its mesh's own frame, shifted where the mesh stands still (v_uv
// carries it: render.gl.material_coordinates): integer hashes only, so the same surface point
// gets the same value on every CPU and as it moves.
#include "hash.glsl"

// A value in [0, 1) per cell of 1/scale metres.
float cell_noise(vec3 p, float scale) {
    return float(hash_u(ivec3(floor(p * scale)))) * (1.0 / 4294967296.0);
}

// Smooth value noise in [0, 1): the cells' values blended across each cell (broad patches
// without edges).
float smooth_noise(vec3 p, float scale) {
    vec3 q = p * scale;
    vec3 i = floor(q);
    vec3 f = q - i;
    f = f * f * (3.0 - 2.0 * f);
    float v = 0.0;
    for (int k = 0; k < 8; ++k) {
        vec3 o = vec3(k & 1, (k >> 1) & 1, (k >> 2) & 1);
        vec3 w = mix(1.0 - f, f, o);
        v += w.x * w.y * w.z * float(hash_u(ivec3(i + o))) * (1.0 / 4294967296.0);
    }
    return v;
}

// 1 where cells 1/scale metres wide span two pixels or more, falling to 0 where a cell is
// under about a pixel (fw: the pixel's footprint in metres), so fine patterns do not alias.
float fade(float fw, float scale) {
    return clamp(2.0 - 2.0 * fw * scale, 0.0, 1.0);
}

// Zero-mean noise of cells 1/scale metres wide, faded out far away.
float octave(vec3 p, float scale, float fw) {
    return (cell_noise(p, scale) - 0.5) * fade(fw, scale);
}

// Zero-mean noise of cells 1/scale metres wide where they span one or two pixels, fading
// out where they are half a pixel or four: the one octave of a ladder that lies at the
// pixel's scale (fw: the footprint in metres).
float band(vec3 p, float scale, float fw) {
    return (cell_noise(p, scale) - 0.5) * fade(0.5 * fw, scale) * (1.0 - fade(2.0 * fw, scale));
}

// `band` in colour: three zero-mean values for a cell from one hash (10 bits each) of the
// cell shifted, so apart from `band`'s own value there: an aggregate's stones differ in hue
// (granite, basalt, limestone) as well as in shade.
vec3 band3(vec3 p, float scale, float fw) {
    uint h = hash_u(ivec3(floor(p * scale)) + ivec3(7919, 104729, 1299709));
    vec3 v = vec3(h & 1023u, (h >> 10) & 1023u, (h >> 20) & 1023u) * (1.0 / 1024.0) - 0.5;
    return v * fade(0.5 * fw, scale) * (1.0 - fade(2.0 * fw, scale));
}

// Grain at pixel size at every distance, zero-mean: cells from 1/finest metres up to 20 cm,
// each octave where it spans about a pixel. Real roads and foliage vary from pixel to pixel
// in a photograph; faded out under the pixel instead, asphalt reads as a car's paint to a
// street model.
float grain_ladder(vec3 p, float fw, float finest) {
    float g = 0.0;
    for (float s = finest; s >= 5.0; s *= 0.5) g += band(p, s, fw);
    return g;
}

// Asphalt's grain, zero-mean: its 6 mm aggregate and coarser stones and binder at pixel
// size at every distance. The wet road's film is broken by the same grain.
float asphalt_grain(vec3 p, float fw) {
    return 0.45 * octave(p, 160.0, fw) + 0.6 * grain_ladder(p, fw, 80.0);
}

// This fragment's asphalt grain, kept by `material` for the wet road's film (the same
// point and footprint), so that a wet road computes it once.
float fragment_asphalt_grain = 0.0;

// Leaf clumps about 1/scale metres apart: each the cell's hashed point grown into a ball lit
// from above (cellular noise), the gaps between the balls in shadow. Mean about 1.
float leaf_clumps(vec3 p, float scale) {
    vec3 q = p * scale;
    vec3 i = floor(q);
    vec3 f = q - i;
    vec4 best = vec4(9.0);
    for (int k = 0; k < 27; ++k) {
        vec3 o = vec3(k % 3, (k / 3) % 3, k / 9) - 1.0;
        uint h = hash_u(ivec3(i + o));
        vec3 d = f - o - vec3(h & 1023u, (h >> 10) & 1023u, (h >> 20) & 1023u) * (1.0 / 1024.0);
        float dd = dot(d, d);
        if (dd < best.x) best = vec4(dd, d);
    }
    const float R = 0.75;  // a clump's radius in cells
    float r = sqrt(best.x) / R;
    if (r >= 1.0) return 0.12;
    vec3 n = best.yzw / R + vec3(0.0, 0.0, sqrt(1.0 - r * r));  // the ball's normal, lifted to face up
    return 0.12 + 1.8 * max(dot(normalize(n), vec3(0.3, 0.2, 0.93)), 0.0);
}

// A joint line of width w (metres) at every multiple of `period` along x, faded like octave.
float joint(float x, float period, float w, float fw) {
    float d = abs(fract(x / period + 0.5) - 0.5) * period;
    return (1.0 - smoothstep(0.5 * w, 0.5 * w + fw, d)) * clamp(2.0 - 2.0 * fw / w, 0.0, 1.0);
}

// Albedo (linear) and gloss (x: reflectance at normal incidence, y: how much of the
// environment the surface reflects) of material `pattern` at object position p. llvmpipe
// runs the body of every `if` below for every pixel (masked), so a program is compiled with
// only the materials its draws show (MATERIAL_n, n the pattern).
vec3 material(int pattern, vec3 p, vec3 c, float fw, out vec2 gloss) {
    gloss = vec2(0.0);
#ifdef MATERIAL_5
    if (pattern == 5) {  // painted metal: a clear coat over the paint
        gloss = vec2(0.12, 0.6);
        return c * (0.97 + 0.06 * cell_noise(p, 60.0));
    }
#endif
#ifdef MATERIAL_6
    if (pattern == 6) {  // glass
        gloss = vec2(0.06, 1.0);
        return c;
    }
#endif
#ifdef MATERIAL_7
    if (pattern == 7) {  // chrome
        gloss = vec2(0.55, 0.9);
        return c * 0.6;
    }
#endif
#ifdef MATERIAL_8
    if (pattern == 8) return c * (0.85 + 0.3 * cell_noise(p, 150.0));  // rubber
#endif
#ifdef MATERIAL_9
    if (pattern == 9) {  // wood: grain across the planks, knots of darker cells
        float grain = fract(dot(p, vec3(0.7, 9.0, 13.0)) + 0.35 * cell_noise(vec3(p.x * 0.25, p.y, p.z), 30.0));
        gloss = vec2(0.03, 0.15);
        return c * (0.80 + 0.22 * grain) * (0.94 + 0.12 * cell_noise(p, 8.0));
    }
#endif
#ifdef MATERIAL_10
    if (pattern == 10) return c * (0.86 + 0.14 * cell_noise(p, 120.0)) * (0.95 + 0.1 * cell_noise(p, 6.0));  // fabric
#endif
#ifdef MATERIAL_11
    if (pattern == 11) {  // leather
        gloss = vec2(0.04, 0.25);
        return c * (0.90 + 0.16 * cell_noise(p, 35.0));
    }
#endif
#ifdef MATERIAL_12
    if (pattern == 12) {  // plastic
        gloss = vec2(0.04, 0.25);
        return c * (0.96 + 0.08 * cell_noise(p, 120.0));
    }
#endif
#ifdef MATERIAL_13
    if (pattern == 13) return c * (0.84 + 0.16 * cell_noise(p, 25.0)) * (0.9 + 0.2 * cell_noise(p, 180.0));  // concrete
#endif
#ifdef MATERIAL_14
    if (pattern == 14) {  // metal: vertical streaks
        gloss = vec2(0.2, 0.35);
        return c * (0.90 + 0.18 * cell_noise(vec3(p.x, p.y, p.z * 0.05), 80.0));
    }
#endif
#ifdef MATERIAL_15
    if (pattern == 15) {  // leaves: lit clumps, shadowed gaps, a hue drifting from yellow to blue green
        float v = mix(1.0, leaf_clumps(p, 4.5), fade(fw, 4.5));
        v *= mix(1.0, leaf_clumps(p, 14.0), fade(fw, 14.0) * 0.5);
        v *= max(1.0 + 1.1 * grain_ladder(p, fw, 80.0), 0.1);  // single leaves and gaps at pixel size
        v *= 0.75 + 0.5 * smooth_noise(p, 2.0);
        vec3 hue = mix(vec3(1.15, 1.05, 0.6), vec3(0.8, 1.0, 1.2), smooth_noise(p, 1.5));
        return c * hue * v;
    }
#endif
#if defined(MATERIAL_16) || defined(MATERIAL_23)
    if (pattern == 16 || pattern == 23) {  // grass: blades, tufts, drier patches; a pitch mown in 5 m stripes
        // Clutter at every scale from blades to tufts, each octave faded where its cells fall
        // under a pixel: some grain stays near pixel size at every distance, as in a
        // photograph of a lawn, where a smooth green reads as paint or fog-grey as asphalt.
        // A lawn lies flat: its broader octaves are noise over the plane (value_noise2), whose
        // spread is 1.16 times the 3D kind's (the amplitudes allow for it).
        float v = 1.0 + 0.45 * octave(p, 80.0, fw) + 0.45 * octave(p, 40.0, fw)
                + 0.52 * (value_noise2(p.xy * 20.0) - 0.5) * fade(fw, 20.0)
                + 0.26 * (value_noise2(p.xy * 6.0) - 0.5) + 0.21 * (value_noise2(p.xy * 1.2) - 0.5);
        float patch = 0.5 + 0.86 * (value_noise2(p.xy * 0.25) * 0.7 + value_noise2(p.xy * 1.1) * 0.3 - 0.5);
        vec3 dry = vec3(0.42, 0.38, 0.18);
        float stripe = pattern == 23 ? 0.92 + 0.16 * mod(floor(p.x / 5.0), 2.0) : 1.0;
        return mix(c, dry, (pattern == 23 ? 0.15 : 0.35) * smoothstep(0.55, 0.9, patch)) * v * stripe;
    }
#endif
#ifdef MATERIAL_17
    if (pattern == 17) {  // asphalt: aggregate, coarser stones and binder, stains, worn areas
        // The mottle between the aggregate (6 mm) and the wear (3 m) is what tells a road
        // from the smooth painted panel of a car's bonnet, which it otherwise resembles. Its
        // stones' hues at the pixel's scale: without them a street model took the grain of a
        // grey road by a lawn for foliage.
        gloss = vec2(0.02, 0.08);
        float wear = smooth_noise(p, 0.3);
        fragment_asphalt_grain = asphalt_grain(p, fw);
        vec3 stones = 1.0 + 0.5 * (band3(p, 80.0, fw) + band3(p, 40.0, fw));
        return c * stones * (1.0 + fragment_asphalt_grain + 0.3 * (smooth_noise(p, 3.0) - 0.5)) * (0.85 + 0.3 * wear);
    }
#endif
#ifdef MATERIAL_18
    if (pattern == 18) {  // paving: 0.5 m slabs, a tone each, dark joints
        float slab = 0.9 + 0.2 * cell_noise(vec3(floor(p.xy * 2.0), 7.0), 1.0);
        float j = max(joint(p.x, 0.5, 0.012, fw), joint(p.y, 0.5, 0.012, fw));
        return c * slab * (1.0 + 0.3 * octave(p, 90.0, fw) + 0.35 * grain_ladder(p, fw, 45.0)) * (1.0 - 0.5 * j);
    }
#endif
#ifdef MATERIAL_19
    if (pattern == 19) {  // brick, running bond on any vertical wall (along x + y), light mortar
        float along = p.x + p.y;
        float course = floor(p.z / 0.075);
        float shifted = along + 0.12 * mod(course, 2.0);
        float tone = 0.8 + 0.35 * cell_noise(vec3(floor(shifted / 0.24), course, 3.0), 1.0);
        float mortar = max(joint(p.z, 0.075, 0.012, fw), joint(shifted, 0.24, 0.012, fw));
        return mix(c * tone * (1.0 + 0.3 * octave(p, 120.0, fw)), vec3(0.62, 0.60, 0.56), 0.8 * mortar);
    }
#endif
#ifdef MATERIAL_20
    if (pattern == 20) {  // plaster: fine grain, broad stains running down from the top
        float stain = cell_noise(vec3(p.x * 0.7, p.y * 0.7, p.z * 0.15), 1.0);
        return c * (1.0 + 0.12 * octave(p, 60.0, fw) + 0.08 * octave(p, 5.0, fw)) * (0.9 + 0.12 * stain);
    }
#endif
#ifdef MATERIAL_21
    if (pattern == 21) {  // bark: furrows along the trunk, between plates a few centimetres wide
        // The plates (6 cm) keep a trunk's bark in view where the 2 cm furrows are under a
        // pixel: a smooth trunk reads as a painted post.
        float furrow = octave(vec3(p.x, p.y, p.z * 0.12), 45.0, fw) + 0.6 * octave(vec3(p.x, p.y, p.z * 0.2), 16.0, fw);
        vec3 moss = mix(c, vec3(0.20, 0.24, 0.10), 0.6 * smoothstep(0.5, 0.8, smooth_noise(p, 3.0)));
        return moss * (1.0 + 0.9 * furrow + 0.3 * octave(p, 8.0, fw));
    }
#endif
#ifdef MATERIAL_22
    if (pattern == 22) {  // roof tiles: courses along the slope, a tone per tile
        float course = floor(p.z / 0.18);
        float tone = 0.85 + 0.25 * cell_noise(vec3(floor((p.x + p.y) / 0.3), course, 5.0), 1.0);
        return c * tone * (1.0 - 0.45 * joint(p.z, 0.18, 0.02, fw));
    }
#endif
#ifdef MATERIAL_24
    if (pattern == 24) {  // wallpaper: stripes of two tones along any wall (x + y), a fine print, seams
        float along = p.x + p.y;
        float band = abs(fract(along / 0.16) - 0.5) * 0.16;  // metres from the nearest stripe's middle
        float stripe = (1.0 - smoothstep(0.035, 0.035 + fw, band)) * clamp(2.0 - 2.0 * fw / 0.08, 0.0, 1.0);
        float print = octave(vec3(along, 0.0, p.z), 70.0, fw);
        return c * (1.0 - 0.12 * stripe + 0.12 * print) * (1.0 - 0.25 * joint(along, 0.53, 0.003, fw));
    }
#endif
#ifdef MATERIAL_27
    if (pattern == 27) {  // shore: sand in broad patches with fine grain, grey pebbles scattered on it
        vec3 sand = c * (0.85 + 0.3 * smooth_noise(p, 2.5)) * (1.0 + 0.3 * octave(p, 120.0, fw));
        vec2 in_cell = fract(p.xy * 16.0) - 0.5;  // a round pebble in some of the 6 cm cells
        float stone = step(0.85, cell_noise(p, 16.0)) * step(length(in_cell), 0.38);
        vec3 pebble = c * vec3(0.85, 0.9, 0.95) * (0.6 + 0.5 * cell_noise(p + 3.0, 16.0));
        return mix(sand, pebble, 0.8 * stone * fade(fw, 16.0));
    }
#endif
#ifdef MATERIAL_26
    if (pattern == 26) {  // floor tiles: 0.3 m squares, a tone each, grey grout joints
        float tone = 0.9 + 0.14 * cell_noise(vec3(floor(p.xy / 0.3), 13.0), 1.0);
        float j = max(joint(p.x, 0.3, 0.005, fw), joint(p.y, 0.3, 0.005, fw));
        return mix(c * tone * (1.0 + 0.08 * octave(p, 70.0, fw)), vec3(0.45, 0.44, 0.42), 0.8 * j);
    }
#endif
#ifdef MATERIAL_25
    if (pattern == 25) {  // seats: a shell every 0.5 m along the row, each a little faded, dark gaps between
        float along = p.x + p.y;
        float seat = floor(along / 0.5);
        float tone = 0.88 + 0.2 * cell_noise(vec3(seat, p.z * 0.0, 11.0), 1.0);
        gloss = vec2(0.04, 0.2);
        return c * tone * (1.0 - 0.8 * joint(along + 0.25, 0.5, 0.07, fw));
    }
#endif
    return c;
}
