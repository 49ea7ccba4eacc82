#version 450
// G-buffer pass, fragment stage (docs/spec.md §1): linear color, linear depth, motion t0→t1 in
// pixels (+y down), object id, and the two-sided motion M_prev = instant − t0 (RG) and
// M_next = t1 − instant (BA), docs/spec.md §17.1. Motion is divided by w here, per fragment.
// Hatched materials (docs/spec.md §5) replace the shading with color · (1 − ink). Emission (§12)
// is added last and never clamped: HDR scenes rely on radiances up to 10^4 reaching every method.

#include "common/hatching.glsl"
#include "common/hatching_threshold.glsl"

in Surface {
    vec4 clip_open;
    vec4 clip_close;
    vec3 world;
    vec3 normal;
    vec2 uv;
    vec3 tone_low;
    vec3 tone_high;
} surface;

layout(location = 0) out vec4 out_color;
layout(location = 1) out float out_depth;
layout(location = 2) out vec2 out_motion;
layout(location = 3) out float out_object_id;
layout(location = 4) out vec4 out_motion_sides;  // discarded where no target is attached

uniform vec2 size;
uniform float near;
uniform vec3 eye;
uniform bool background;
uniform vec4 background_color;
uniform mat4 sky_from_clip;
uniform mat4 sky_projection[2];

uniform vec3 light_direction;  // toward the light
uniform vec3 light_color;
uniform vec3 ambient;
uniform vec4 material_color;
uniform vec3 material_emission;  // radiance: emission colour x strength
uniform float material_specular;
uniform float material_shininess;
uniform bool has_texture;
uniform int object_id;
layout(binding = 0) uniform sampler2D albedo_map;
const int hatching = HATCHING;  // 0 none, 1 six_way, 2 threshold: one program each
uniform float hatching_scale;
layout(binding = 1) uniform sampler2D tam_low;   // six_way: tones 1–3; threshold: thresholds
layout(binding = 2) uniform sampler2D tam_high;  // six_way: tones 4–6
// Alpha (docs/spec.md §20): 0 opaque, 1 mask (discarded below alpha_cutoff), 2 blend, 3 additive.
uniform int alpha_mode;
uniform float alpha_cutoff;

#if LAYERS
// Fragment lists of translucent surfaces (docs/spec.md §20, src/passes/gbuffer.h): fragment k of
// pixel (x, y) is stored at texel (x, y + k·H); the count includes fragments past the capacity.
layout(binding = 0, r32ui) uniform coherent uimage2D fragment_counts;
layout(binding = 1, rgba32f) uniform writeonly image2D fragment_surface;
layout(binding = 2, rgba32f) uniform writeonly image2D fragment_motion;
layout(binding = 3) uniform sampler2D opaque_depth;
uniform int layer_capacity;

// Appends this fragment unless the opaque surface hides it: premultiplied colour and coverage
// (additive surfaces cover nothing), then depth, motion and the alpha mode.
void append_fragment(vec4 color, float depth, vec2 motion) {
    ivec2 p = ivec2(gl_FragCoord.xy);
    if (!(depth < texelFetch(opaque_depth, p, 0).r)) return;
    float alpha = clamp(color.a, 0.0, 1.0);
    uint index = imageAtomicAdd(fragment_counts, p, 1u);
    if (index >= uint(layer_capacity)) return;
    // fragment_layout's blocks (blurlab.translucency): as many rows of H x W as the image holds.
    int rows = imageSize(fragment_surface).y / int(size.y);
    ivec2 q = ivec2(p.x + int(index) / rows * int(size.x), p.y + int(index) % rows * int(size.y));
    imageStore(fragment_surface, q, vec4(color.rgb * alpha, alpha_mode == 3 ? 0.0 : alpha));
    imageStore(fragment_motion, q, vec4(depth, motion, float(alpha_mode)));
}
#endif

// Clip position -> pixel position, x right, y down (the projection has y flipped). w is the
// point's view depth. A point closer than the near plane at t0 or t1 (or behind the eye) has no
// image position there; it is placed as if on the near plane, so its motion stays finite and
// points the way the point moved.
vec2 to_pixels(vec4 clip) {
    float w = max(clip.w, near);
    return (clip.xy / w * 0.5 + 0.5) * size;
}

void main() {
    if (background) {
        // Points at infinity move only with the camera's rotation.
        vec2 ndc = gl_FragCoord.xy / size * 2.0 - 1.0;
        vec4 far_point = sky_from_clip * vec4(ndc, 1.0, 1.0);
        vec3 direction = far_point.xyz / far_point.w;
        vec4 sky_open = sky_projection[0] * vec4(direction, 0.0);
        vec4 sky_close = sky_projection[1] * vec4(direction, 0.0);
        // Directions behind the camera at t0 or t1 have no image position: no motion then.
        vec2 open = sky_open.xy / max(sky_open.w, 1e-20);
        vec2 close = sky_close.xy / max(sky_close.w, 1e-20);
        bool seen = sky_open.w > 0.0 && sky_close.w > 0.0;
        out_color = background_color;
        out_depth = uintBitsToFloat(0x7F800000u);  // +inf
        out_motion = seen ? (close - open) * 0.5 * size : vec2(0.0);
        out_object_id = -1.0;
        // The instant's own image position is the pixel center (ndc above).
        out_motion_sides = seen ? vec4(ndc - open, close - ndc) * 0.5 * size.xyxy : vec4(0.0);
        return;
    }
    vec4 albedo = material_color;
    if (has_texture) albedo *= texture(albedo_map, surface.uv);
    if (alpha_mode == 1 && albedo.a < alpha_cutoff) discard;
    vec3 n = normalize(surface.normal);
    vec3 v = normalize(eye - surface.world);
    if (dot(n, v) < 0.0) n = -n;  // two-sided: the inside of the teapot is lit too
    vec3 l = normalize(light_direction);
    float diffuse = max(dot(n, l), 0.0);
    float specular = 0.0;
    if (diffuse > 0.0 && material_specular > 0.0)
        specular = material_specular * pow(max(dot(n, normalize(l + v)), 0.0), material_shininess);
    out_color = vec4(albedo.rgb * (ambient + light_color * diffuse) + light_color * specular,
                     albedo.a);
    if (hatching == 1) {
        vec2 tam_uv = surface.uv * hatching_scale;
        float ink = dot(surface.tone_low, texture(tam_low, tam_uv).rgb) +
                    dot(surface.tone_high, texture(tam_high, tam_uv).rgb);
        out_color = vec4(albedo.rgb * (1.0 - clamp(ink, 0.0, 1.0)), albedo.a);
    } else if (hatching == 2) {
        float intensity = hatching_intensity(n, v, l, light_color, ambient, material_specular,
                                             material_shininess);
        float ink = threshold_ink(tam_low, surface.uv * hatching_scale, 1.0 - intensity);
        out_color = vec4(albedo.rgb * (1.0 - ink), albedo.a);
    }
    out_color.rgb += material_emission;
    // clip.w is the view depth, and the rasterizer interpolates 1/w for perspective correction
    // anyway: no separate varying is needed.
    out_depth = 1.0 / gl_FragCoord.w;
    vec2 open = to_pixels(surface.clip_open), close = to_pixels(surface.clip_close);
    out_motion = close - open;
    out_object_id = float(object_id);
    // The surface point seen at this pixel center at the instant is at gl_FragCoord.xy then
    // (its instant clip position, divided): the two halves of its motion meet there.
    out_motion_sides = vec4(gl_FragCoord.xy - open, close - gl_FragCoord.xy);
#if LAYERS
    append_fragment(out_color, out_depth, out_motion);
#endif
}
