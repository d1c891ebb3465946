
#version 330
uniform vec3 rain_colour;
uniform float rain_alpha;
in float v_depth;
layout(location = 0) out vec4 out_colour;
void main() { out_colour = vec4(rain_colour, rain_alpha * clamp(2.0 / max(v_depth, 0.5), 0.15, 1.0)); }
