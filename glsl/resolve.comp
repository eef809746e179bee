#version 450
// Supersampling resolve: each output pixel is the box average of its K x K samples, in linear
// radiance (before tone mapping), K = input size / output size.

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 6, rgba16f) readonly uniform image2D samples;
layout(set = 0, binding = 7, rgba16f) writeonly uniform image2D resolved;

void main() {
    ivec2 size = imageSize(resolved);
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, size))) return;
    ivec2 k = imageSize(samples) / size;
    vec3 sum = vec3(0.0);
    for (int y = 0; y < k.y; ++y) {
        for (int x = 0; x < k.x; ++x) {
            sum += imageLoad(samples, p * k + ivec2(x, y)).rgb;
        }
    }
    imageStore(resolved, p, vec4(sum / float(k.x * k.y), 1.0));
}
