uniform float exposure;
vec3 tone(vec3 c) { return pow(vec3(1.0) - exp(-exposure * c), vec3(1.0 / 2.2)); }
