uniform vec3 sky_zenith;
uniform vec3 sky_horizon;
uniform vec3 sun_dir;
uniform vec3 sun_colour;
uniform vec3 fog_colour;
uniform float fog_per_m;
vec3 sky(vec3 dir) {
    float up = clamp(dir.z, -0.2, 1.0);
    vec3 c = mix(sky_horizon, sky_zenith, smoothstep(0.0, 0.6, up));
    if (up < 0.0) c = sky_horizon * 0.8;
    float sd = dot(dir, sun_dir);
    c += sun_colour * (smoothstep(0.9994, 0.9997, sd) * 8.0 + pow(max(sd, 0.0), 64.0) * 0.25);
    float fogged = 1.0 - exp(-fog_per_m * 180.0);  // the sky is seen through the fog
    return mix(c, fog_colour, fogged);
}
