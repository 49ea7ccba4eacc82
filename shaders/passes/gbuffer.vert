#version 450
// G-buffer pass, vertex stage (docs/spec.md §1). Index 0 = shutter open t0, 1 = close t1, 2 = the
// G-buffer's instant. Positions at t0 and t1 go to the rasterizer undivided (see gbuffer.frag).
// Hatched materials (docs/spec.md §5, six_way) get their tone weights here, per vertex.

#include "common/hatching.glsl"

layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
layout(location = 2) in vec2 texcoord;
layout(location = 3) in uvec4 bone_index;
layout(location = 4) in vec4 bone_weight;

uniform mat4 model[3];
uniform mat4 view_projection[3];  // y flipped: see src/passes/gbuffer.h
uniform int bone_count;
uniform bool background;
const int hatching = HATCHING;  // 0 none, 1 six_way, 2 threshold: one program each
uniform vec3 eye;
uniform vec3 light_direction;
uniform vec3 light_color;
uniform vec3 ambient;
uniform float material_specular;
uniform float material_shininess;

// Bone matrices: bone_count at t0, then bone_count at t1, then bone_count at the instant.
layout(std430, binding = 0, row_major) readonly buffer Bones { mat4 bones[]; };

out Surface {
    vec4 clip_open;
    vec4 clip_close;
    vec3 world;
    vec3 normal;
    vec2 uv;
    vec3 tone_low;   // six_way weights of tones 1–3
    vec3 tone_high;  // and of tones 4–6
} surface;

// Object to world at `time` (0, 1, 2 as model[]). Unskinned meshes take the model matrix
// as it is: the same bits as model times an identity skinning matrix, without three 4x4
// products per vertex.
mat4 placement(int time) {
    if (bone_count == 0) return model[time];
    mat4 m = mat4(0.0);
    for (int i = 0; i < 4; ++i) m += bone_weight[i] * bones[time * bone_count + int(bone_index[i])];
    return model[time] * m;
}

void main() {
    if (background) {
        // One triangle that covers the image, at the far plane.
        vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2) * 2.0 - 1.0;
        gl_Position = vec4(p, 1.0, 1.0);
        return;
    }
    vec4 p = vec4(position, 1.0);
    mat4 at_instant = placement(2);
    vec4 world = at_instant * p;
    surface.clip_open = view_projection[0] * (placement(0) * p);
    surface.clip_close = view_projection[1] * (placement(1) * p);
    surface.world = world.xyz;
    surface.normal = transpose(inverse(mat3(at_instant))) * normal;
    surface.uv = texcoord;
    surface.tone_low = vec3(0.0);
    surface.tone_high = vec3(0.0);
    if (hatching == 1) {
        vec3 n = normalize(surface.normal);
        vec3 v = normalize(eye - surface.world);
        if (dot(n, v) < 0.0) n = -n;  // two-sided, as in gbuffer.frag
        float intensity = hatching_intensity(n, v, normalize(light_direction), light_color,
                                             ambient, material_specular, material_shininess);
        six_way_weights(intensity, surface.tone_low, surface.tone_high);
    }
    gl_Position = view_projection[2] * world;
}
