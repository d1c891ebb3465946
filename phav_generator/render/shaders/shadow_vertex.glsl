
#version 330
uniform mat4 light_vp;
in vec3 in_pos;
in uvec4 in_ids;

#include "models.glsl"

void main() { gl_Position = light_vp * (model(in_ids.x, 0) * vec4(in_pos, 1.0)); }
