uniform sampler2D models;
mat4 model(uint object, int at) {
    ivec2 c = ivec2(4 * at, int(object));
    return mat4(texelFetch(models, c, 0), texelFetch(models, c + ivec2(1, 0), 0),
                texelFetch(models, c + ivec2(2, 0), 0), texelFetch(models, c + ivec2(3, 0), 0));
}
