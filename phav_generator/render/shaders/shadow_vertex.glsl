
#version 330
uniform mat4 light_vp;
in vec3 in_pos;
in uvec4 in_bones;
in vec4 in_weights;

#include "models.glsl"

void main() { gl_Position = light_vp * (skin(in_bones, in_weights, 0) * vec4(in_pos, 1.0)); }
