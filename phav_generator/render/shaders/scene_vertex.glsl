
#version 330
uniform mat4 view_t;
uniform mat4 view_t1;
uniform mat4 proj;
uniform mat4 light_vp;
in vec3 in_pos;
in vec3 in_normal;
in uvec4 in_ids;  // drawable, pixel class, instance, material × 256 + pattern
in uvec4 in_bones;  // rows of the models texture
in vec4 in_weights;
in vec3 in_colour;
in vec3 in_emission;
in vec3 in_uv;  // texture coordinates and layer (textured surfaces)
out vec3 v_normal;
out vec3 v_world;
out vec3 v_uv;
out float v_depth;
out vec4 v_clip1;
out vec4 v_light;
flat out uint v_class;
flat out uint v_instance;
flat out int v_material;
flat out int v_pattern;
flat out vec3 v_colour;
flat out vec3 v_emission;

#include "models.glsl"

void main() {
    mat4 model_t = skin(in_bones, in_weights, 0);
    vec4 world = model_t * vec4(in_pos, 1.0);
    vec4 cam = view_t * world;
    v_depth = -cam.z;
    v_world = world.xyz;
    v_uv = in_uv;
    v_normal = mat3(model_t) * in_normal;
    v_light = light_vp * world;
#if FLOW  // the labelled pass: where this point is at t + 1, for its forward flow
    v_clip1 = proj * (view_t1 * (skin(in_bones, in_weights, 1) * vec4(in_pos, 1.0)));
#else
    v_clip1 = vec4(0.0);
#endif
    v_class = in_ids.y;
    v_instance = in_ids.z;
    v_material = int(in_ids.w / 256u);
    v_pattern = int(in_ids.w % 256u);
    v_colour = in_colour;
    v_emission = in_emission;
    gl_Position = proj * cam;
}
