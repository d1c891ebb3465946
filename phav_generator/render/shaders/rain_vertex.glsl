
#version 330
uniform mat4 view_t;
uniform mat4 proj;
in vec3 in_pos;
out float v_depth;
void main() {
    vec4 cam = view_t * vec4(in_pos, 1.0);
    v_depth = -cam.z;
    gl_Position = proj * cam;
}
