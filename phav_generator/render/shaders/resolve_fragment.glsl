
#version 330
uniform sampler2D samples;  // the samples' images side by side, each one frame wide
uniform int count;
uniform int width;
out vec4 out_colour;
void main() {
    ivec2 px = ivec2(gl_FragCoord.xy);
    vec4 acc = vec4(0.0);
    for (int i = 0; i < count; ++i) acc += texelFetch(samples, px + ivec2(i * width, 0), 0);
    out_colour = acc / float(count);
}
