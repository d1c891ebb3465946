
#version 330
uniform uint sky_class;
uniform vec4 intrinsics;  // fx, fy, cx, cy (image convention)
uniform vec2 size;
uniform vec2 origin;  // the viewport's lower-left corner in the target
uniform mat3 cam_rot;  // camera → world

#include "sky.glsl"

#include "tone.glsl"

#include "outputs.glsl"

void main() {
    vec2 xy = gl_FragCoord.xy - origin;  // GL window coordinates, y up: image row v = size.y − y
    vec3 dir_cam = vec3((xy.x - intrinsics.z) / intrinsics.x, (xy.y - size.y + intrinsics.w) / intrinsics.y, -1.0);
    out_colour = vec4(tone(sky(normalize(cam_rot * dir_cam))), 0.0);
    out_class = sky_class;
    out_instance = 0u;
    out_depth = 1.0 / 0.0;
    out_flow = vec4(0.0);
}
