layout(location = 0) out vec4 out_colour;
layout(location = 1) out uint out_class;
layout(location = 2) out uint out_instance;
layout(location = 3) out float out_depth;
layout(location = 4) out vec4 out_flow;
