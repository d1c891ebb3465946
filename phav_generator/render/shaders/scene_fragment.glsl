
uniform vec3 sky_ambient;
uniform vec3 ground_ambient;
uniform float wetness;
uniform vec3 eye;
uniform vec2 size;
uniform sampler2DShadow shadow_map;  // the sun's depth map of what moves, drawn every frame
uniform sampler2DShadow still_shadow_map;  // ... of what holds still, drawn once
uniform sampler2DArray textures;  // people's clothes, one layer per outfit
uniform int lamp_count;
uniform vec3 lamp_pos[16];
uniform vec3 lamp_colour;
in vec3 v_normal;
in vec3 v_world;
in vec3 v_uv;
in float v_depth;
in vec4 v_clip1;
in vec4 v_light;
flat in uint v_class;
flat in uint v_instance;
flat in int v_material;
flat in int v_pattern;
flat in vec3 v_colour;          // linear (display colour to the power 2.2, done once on the CPU)
flat in vec3 v_emission;

#include "sky.glsl"

#include "tone.glsl"

#include "outputs.glsl"

#if MATERIALS
#include "materials.glsl"
#endif

float sunlit(vec3 n) {
#if !SHADOWS && !STILL_SHADOWS
    return 1.0;
#endif
    vec3 p = v_light.xyz / v_light.w * 0.5 + 0.5;
    if (p.x <= 0.0 || p.x >= 1.0 || p.y <= 0.0 || p.y >= 1.0 || p.z >= 1.0) return 1.0;
    float bias = 0.0015 + 0.004 * (1.0 - abs(dot(n, sun_dir)));
    vec3 q = vec3(p.xy, p.z - bias);
    float lit = 1.0;  // 2×2 percentage-closer (linear filter) in each map; the darker wins
#if SHADOWS
    lit = texture(shadow_map, q);
#endif
#if STILL_SHADOWS
    lit = min(lit, texture(still_shadow_map, q));
#endif
    return lit;
}

// fw: the pixel's footprint (m) for the materials' fine detail.
vec3 albedo(float fw, out vec2 gloss) {
    // A texture image (linear colours), its mip level from derivatives taken outside the branch.
    vec2 du = dFdx(v_uv.xy), dv = dFdy(v_uv.xy);
    gloss = vec2(0.0);
    if (v_pattern == 4) return textureGrad(textures, v_uv, du, dv).rgb;
    vec3 c = v_colour;
#if MATERIALS
    if (v_pattern >= 5) return material(v_pattern, v_uv, c, fw, gloss);
#endif
    if (v_pattern == 3) {  // speckle noise (ground grain), from the world position
        vec2 cell = floor(v_world.xy * 2.0);
        float h = fract(sin(dot(cell, vec2(12.9898, 78.233))) * 43758.5453);
        c *= 0.88 + 0.24 * h;
    }
    return c;
}

// Open water's surface normal: ripples at two scales, from integer-hash value noise over
// the world position (still water: the waves do not move, so the flow stays exact).
vec3 ripples(vec2 q) {
    const float e = 0.04;
    float h0 = value_noise2(q * 1.3) + 0.5 * value_noise2(q * 3.7);
    float hx = value_noise2((q + vec2(e, 0.0)) * 1.3) + 0.5 * value_noise2((q + vec2(e, 0.0)) * 3.7);
    float hy = value_noise2((q + vec2(0.0, e)) * 1.3) + 0.5 * value_noise2((q + vec2(0.0, e)) * 3.7);
    return normalize(vec3(-0.06 * (hx - h0) / e, -0.06 * (hy - h0) / e, 1.0));
}

void main() {
    out_class = v_class;
    out_instance = v_instance;
    out_depth = v_depth;
    if (v_clip1.w > 1e-6) {
        vec2 window1 = (v_clip1.xy / v_clip1.w * 0.5 + 0.5) * size;
        vec2 d = window1 - gl_FragCoord.xy;
        out_flow = vec4(d.x, -d.y, 1.0, 0.0);  // image rows grow downwards
    } else {
        out_flow = vec4(0.0);  // behind the camera at t + 1: invalid
    }
#if !COLOUR
    out_colour = vec4(0.0);  // labels only: the supersampled passes shade the raw colour
#else
    vec3 n = normalize(v_normal);
    if (!gl_FrontFacing) n = -n;
    if (v_material == 2) n = ripples(v_world.xy);
    vec2 gloss;
    float fw = length(fwidth(v_uv));  // outside any branch: derivatives need every pixel of the quad
    vec3 a = albedo(fw, gloss);
    float reflectivity = 0.0;
#if WET
    float wet = (v_material == 1 && n.z > 0.7) ? wetness : 0.0;
    if (v_material == 2) wet = 1.0;
    // Water fills the pores of asphalt, soil and stone and darkens them; it beads on the
    // waxy blades of grass, which darken little and, facing every way, scatter its
    // reflection (a lawn that mirrored the sky read as a hedge); it pools on hard ground.
    bool grass = v_pattern == 16 || v_pattern == 23;
    a *= 1.0 - (grass ? 0.05 : 0.45) * wet;
#else
    float wet = 0.0;
#endif
    float hemi = 0.5 + 0.5 * n.z;
    vec3 light = mix(ground_ambient, sky_ambient, hemi);
    float facing = max(dot(n, sun_dir), 0.0);
    float shade = (facing > 0.0 || wet > 0.0) ? sunlit(n) : 0.0;  // the shadow map only where it matters
    light += sun_colour * facing * shade;
#if LAMPS
    for (int i = 0; i < lamp_count; ++i) {
        vec3 d = lamp_pos[i] - v_world;
        float r2 = dot(d, d);
        light += lamp_colour * max(dot(n, d * inversesqrt(r2)), 0.0) * 5.0 / (1.0 + r2);
    }
#endif
    vec3 c = a * light + v_emission;
#if MATERIALS
    if (gloss.y > 0.0) {  // glossy assets: the sky (or the dark ground below it) and the sun mirrored
        vec3 to_eye = normalize(eye - v_world);
        vec3 mirrored = reflect(-to_eye, n);
        float f = gloss.x + (1.0 - gloss.x) * pow(1.0 - max(dot(n, to_eye), 0.0), 5.0);
        vec3 env = mirrored.z > 0.0 ? sky(mirrored) : ground_ambient * 0.25;
        c = mix(c, env, gloss.y * f);
        c += sun_colour * pow(max(dot(mirrored, sun_dir), 0.0), 120.0) * 2.0 * gloss.y * shade;
    }
#endif
#if WET
    if (wet > 0.0 && !grass) {
        vec3 to_eye = normalize(eye - v_world);
        float cosv = max(dot(n, to_eye), 0.0);
        // Water's reflectance (Schlick, 2 % head-on): a wet road is dark under the camera
        // and shines only towards the horizon.
        float fresnel = 0.02 + 0.98 * pow(1.0 - cosv, 5.0);
        // Water stands in puddles in the road's dips and mirrors the sky there; between them
        // damp asphalt, rough, reflects a blurred third as much. A film over the whole road
        // would be a mirror as uniform as a car's bonnet.
        float dips = smoothstep(0.5, 0.62, 0.7 * value_noise2(v_world.xy * 0.35) + 0.3 * value_noise2(v_world.xy * 1.3));
        float damp = 0.35;
#if MATERIALS
        // Damp asphalt is rough: its stones stand out of the film, which shines between them.
        if (v_pattern == 17) damp *= max(1.0 + 2.5 * fragment_asphalt_grain, 0.0);
#endif
        float pools = v_material == 2 ? 1.0 : mix(damp, 1.0, dips);  // open water: all of it
        reflectivity = wet * pools * fresnel;
        vec3 mirrored = reflect(-to_eye, n);
        c = mix(c, sky(mirrored) * 0.8, reflectivity * 0.8);
        c += sun_colour * pow(max(dot(mirrored, sun_dir), 0.0), 200.0) * 3.0 * wet * pools * shade;
    }
#endif
    c = mix(c, fog_colour, 1.0 - exp(-fog_per_m * v_depth));
    out_colour = vec4(tone(c), reflectivity);
#endif
}
