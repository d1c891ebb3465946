uniform vec3 sky_zenith;
uniform vec3 sky_horizon;
uniform vec3 sky_glow;  // the low sun's, at the horizon in its quarter
uniform vec3 sky_tint;  // the colour balance of an overcast deck (lighting.py)
uniform vec3 sun_dir;
uniform vec3 sun_colour;
uniform vec3 fog_colour;
uniform float fog_per_m;
uniform float cloud_cover;  // 0 clear … 1 overcast

#include "hash.glsl"

vec3 sky(vec3 dir) {
    float up = clamp(dir.z, -0.2, 1.0);
    // The low sun's glow hugs the horizon in its quarter of the sky: from its full strength
    // towards the sun to none at right angles to it.
    vec2 flat_dir = dir.xy + vec2(1e-6, 0.0);
    vec2 flat_sun = sun_dir.xy + vec2(1e-6, 0.0);
    float toward = max(dot(normalize(flat_dir), normalize(flat_sun)), 0.0);
    vec3 horizon = sky_horizon + sky_glow * toward * toward * (1.0 - smoothstep(0.0, 0.4, max(up, 0.0)));
    vec3 c = mix(horizon, sky_zenith, smoothstep(0.0, 0.6, up));
    if (up < 0.0) c = horizon * 0.8;
    if (cloud_cover > 0.0 && dir.z > 0.01) {
        // A layer of cloud 1 km up: four octaves over where the ray meets it, its cover
        // growing with the θ's cloud intensity, lit on top and grey beneath, thinning to the
        // horizon. Closing up, it thickens into an overcast deck without bellies (stratus).
        vec2 at = dir.xy / dir.z * 1.0;
        float n = 0.5 * value_noise2(at * 1.5) + 0.25 * value_noise2(at * 3.1) + 0.15 * value_noise2(at * 6.3)
                  + 0.1 * value_noise2(at * 12.7);
        float cover = smoothstep(1.0 - cloud_cover - 0.05, 1.0 - cloud_cover + 0.25, n);
        vec3 lit = max(max(horizon.r, horizon.g), horizon.b) * vec3(1.08, 1.08, 1.1);
        vec3 cloud = mix(lit, lit * mix(0.62, 1.0, smoothstep(0.6, 0.9, cloud_cover)), smoothstep(0.45, 0.95, n));
        c = mix(c, cloud, cover * smoothstep(0.0, 0.04, dir.z));
    }
    c *= sky_tint;
    float sd = dot(dir, sun_dir);
    c += sun_colour * (smoothstep(0.9994, 0.9997, sd) * 8.0 + pow(max(sd, 0.0), 64.0) * 0.25);
    float fogged = 1.0 - exp(-fog_per_m * 180.0);  // the sky is seen through the fog
    return mix(c, fog_colour, fogged);
}
