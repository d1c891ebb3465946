
uniform sampler2D colour_ss;   // raw colour (supersampled, resolved), linear filtering; alpha = reflectivity
uniform sampler2D depth_1x;    // metres along the axis, inf = sky
uniform sampler2D flow_1x;     // image-convention pixels, z = valid
uniform vec4 intrinsics;
uniform vec2 size;
uniform mat3 cam_rot;
uniform vec3 up_cam;          // world +Z in camera coordinates
uniform float motion_blur;    // shutter fraction of a frame
uniform float ao_strength;
uniform float fog_per_m;      // the fog's extinction: occlusion darkens only the light that comes through it
uniform float bloom;
uniform float vignette;
uniform vec3 grade_gain;
uniform float grade_lift;
uniform float saturation;
out vec4 out_colour;

// Ambient-occlusion tap directions (4 unit vectors, each used with its opposite) and bloom
// taps (6 on a 5 px ring, each a bilinear 2 × 2 average): constants, no per-pixel trigonometry.
const vec2 AO_TAPS[4] = vec2[4](vec2(0.92388, 0.38268), vec2(0.38268, 0.92388), vec2(-0.38268, 0.92388),
    vec2(-0.92388, 0.38268));
const vec2 BLOOM_TAPS[6] = vec2[6](vec2(4.33013, 2.5), vec2(0.0, 5.0), vec2(-4.33013, 2.5), vec2(-4.33013, -2.5),
    vec2(0.0, -5.0), vec2(4.33013, -2.5));

float depth_at(vec2 px) { return texture(depth_1x, px / size).r; }

vec3 cam_point(vec2 px, float d) {  // px: GL window coordinates (y up), pixel centres at +0.5
    float v_img = size.y - px.y;
    return vec3((px.x - intrinsics.z) * d / intrinsics.x, -(v_img - intrinsics.w) * d / intrinsics.y, -d);
}

vec2 to_window(vec3 p) {
    float z = -p.z;
    return vec2(intrinsics.z + intrinsics.x * p.x / z, size.y - (intrinsics.w - intrinsics.y * p.y / z));
}

void main() {
    vec2 px = gl_FragCoord.xy;
    vec2 uv = px / size;
    vec3 c = texture(colour_ss, uv).rgb;
    vec4 fl = texture(flow_1x, uv);
#if MOTION_BLUR
    vec2 step = vec2(fl.x, -fl.y) * motion_blur;
    // Only where the shutter smears a quarter pixel or more; a loop no pixel of a block
    // enters costs nothing (llvmpipe runs both sides of an if, but exits idle loops).
    int taps = (fl.z > 0.5 && dot(step, step) > 0.0625) ? 4 : 0;
    vec3 acc = vec3(0.0);
    for (int i = 0; i < taps; ++i) acc += texture(colour_ss, (px + step * (float(i) / 3.0 - 0.5)) / size).rgb;
    if (taps > 0) c = acc / 4.0;
#endif
    float d = depth_at(px);
#if SSR
    float reflectivity = texture(colour_ss, uv).a;
    if (reflectivity > 0.01 && d < 1e30) {
        vec3 p = cam_point(px, d);
        vec3 r = reflect(normalize(p), normalize(up_cam));
        float t = 0.15;
        for (int i = 0; i < 24; ++i) {
            vec3 q = p + r * t;
            if (-q.z < 0.05) break;
            vec2 w = to_window(q);
            if (w.x < 0.0 || w.y < 0.0 || w.x >= size.x || w.y >= size.y) break;
            float seen = depth_at(w);
            if (seen < -q.z - 0.03 && seen > -q.z - 1.5) {
                vec3 hit = texture(colour_ss, w / size).rgb;
                float fade = 1.0 - smoothstep(0.8, 1.0, max(abs(w.x / size.x - 0.5), abs(w.y / size.y - 0.5)) * 2.0);
                c = mix(c, hit, reflectivity * 0.7 * fade);
                break;
            }
            t *= 1.22;
        }
    }
#endif
#if AO
    if (d < 1e30) {
        // Each tap nearer than the plane through this pixel occludes it, fading with the
        // tap's distance in space: a wall's corner, a fold or a foot on the floor darken what
        // is near them, and a thin chair leg does not print a copy of itself on floor half a
        // metre before or behind it (a depth test alone cannot tell that floor from a crease).
        // Inverse depth is affine in window coordinates on a plane; its slope comes from the
        // neighbour on each axis that agrees better, so a silhouette does not bend it.
        float iz = 1.0 / d;
        vec2 ahead = vec2(1.0 / depth_at(px + vec2(1.0, 0.0)), 1.0 / depth_at(px + vec2(0.0, 1.0))) - iz;
        vec2 behind = iz - vec2(1.0 / depth_at(px - vec2(1.0, 0.0)), 1.0 / depth_at(px - vec2(0.0, 1.0)));
        vec2 slope = mix(behind, ahead, lessThan(abs(ahead), abs(behind)));
        vec3 p = cam_point(px, d);
        float radius = clamp(0.45 * intrinsics.x / d, 2.0, 10.0);
        float reach = radius * d / intrinsics.x;  // the taps' span in metres
        float occluded = 0.0;
        for (int i = 0; i < 8; ++i) {
            // Whole-pixel offsets: the depth is read unfiltered, at pixel centres.
            vec2 off = floor(radius * (i < 4 ? AO_TAPS[i] : -AO_TAPS[i - 4]) + 0.5);
            float a = min(depth_at(px + off), 1e6);  // the sky: far, not infinite
            float plane = iz + dot(slope, off);
            float nearer = plane > 0.0 ? 1.0 / plane - a : 1e6;
            float apart = length(cam_point(px + off, a) - p);
            occluded += smoothstep(0.02, 0.1, nearer) * (1.0 - smoothstep(0.5 * reach, 1.5 * reach, apart));
        }
        c *= 1.0 - ao_strength * min(occluded / 6.0, 1.0) * exp(-fog_per_m * d);
    }
#endif
#if BLOOM
    {
        vec3 glow = vec3(0.0);
        for (int i = 0; i < 6; ++i) glow += max(texture(colour_ss, (px + BLOOM_TAPS[i]) / size).rgb - 0.75, 0.0);
        c += bloom * glow / 6.0;
    }
#endif
#if GRADING
    c = c * grade_gain + grade_lift;
    float luma = dot(c, vec3(0.2126, 0.7152, 0.0722));
    c = mix(vec3(luma), c, saturation);
    c = c + 0.06 * (c - 0.5) * (1.0 - abs(2.0 * c - 1.0));  // gentle S-curve
#endif
    vec2 q = uv - 0.5;
    c *= 1.0 - vignette * dot(q, q) * 2.0;
    out_colour = vec4(clamp(c, 0.0, 1.0), 1.0);
}
