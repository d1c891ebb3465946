uniform sampler2D models;
mat4 model(uint row, int at) {
    ivec2 c = ivec2(4 * at, int(row));
    return mat4(texelFetch(models, c, 0), texelFetch(models, c + ivec2(1, 0), 0),
                texelFetch(models, c + ivec2(2, 0), 0), texelFetch(models, c + ivec2(3, 0), 0));
}
// Linear blend skinning: the weighted sum of up to four bones' matrices at frame t (at = 0)
// or t + 1 (at = 1). A rigid mesh has one bone of weight 1.
mat4 skin(uvec4 bones, vec4 weights, int at) {
    mat4 m = weights.x * model(bones.x, at);
    if (weights.y > 0.0) m += weights.y * model(bones.y, at);
    if (weights.z > 0.0) m += weights.z * model(bones.z, at);
    if (weights.w > 0.0) m += weights.w * model(bones.w, at);
    return m;
}
