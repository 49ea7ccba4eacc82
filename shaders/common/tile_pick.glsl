// The choice both engine_eevee tile passes make (docs/spec.md §17.2 steps 1-2), per side (xy:
// prev, zw: next): among the candidates a tile scans in row-major order, the longest, the first
// in that order among equal lengths, vec4(0) where there is none. An invocation offers its
// candidates in increasing scan index; with a work group per tile, group_pick() then merges
// the invocations' picks on the key (longest length, then smallest index), which picks the
// same candidate as one invocation scanning them all. pick_tiles() runs either mode for the
// including pass, which defines scan() and store_pick(). NumPy twin: blurlab.twins.eevee.

// A work group of 16 x 16 invocations serves one tile; one invocation per tile uses the same
// group shape.
const int PICK_GROUP_SIDE = 16;
const uint PICK_GROUP_SIZE = uint(PICK_GROUP_SIDE * PICK_GROUP_SIDE);
layout(local_size_x = PICK_GROUP_SIDE, local_size_y = PICK_GROUP_SIDE) in;

const int NO_CANDIDATE = 0x7fffffff;

// This invocation's pick so far. The first candidate offered replaces it, even at length 0.
vec4 picked = vec4(0.0);
vec2 picked_length = vec2(-1.0);
ivec2 picked_index = ivec2(NO_CANDIDATE);

void pick_prev(vec2 v, float len, int index) {
    picked.xy = v;
    picked_length.x = len;
    picked_index.x = index;
}

void pick_next(vec2 v, float len, int index) {
    picked.zw = v;
    picked_length.y = len;
    picked_index.y = index;
}

shared vec4 group_picked[PICK_GROUP_SIZE];
shared vec2 group_length[PICK_GROUP_SIZE];
shared ivec2 group_index[PICK_GROUP_SIZE];

// Whether invocation j's pick on `side` beats invocation i's.
bool pick_beats(uint j, uint i, int side) {
    float lj = group_length[j][side], li = group_length[i][side];
    return lj > li || (lj == li && group_index[j][side] < group_index[i][side]);
}

// The work group's pick, from every invocation's; call it in uniform control flow. Valid in
// invocation 0.
vec4 group_pick() {
    uint i = gl_LocalInvocationIndex;
    group_picked[i] = picked;
    group_length[i] = picked_length;
    group_index[i] = picked_index;
    barrier();
    for (uint stride = PICK_GROUP_SIZE / 2u; stride > 0u; stride >>= 1u) {
        if (i < stride) {
            uint j = i + stride;
            if (pick_beats(j, i, 0)) {
                group_picked[i].xy = group_picked[j].xy;
                group_length[i].x = group_length[j].x;
                group_index[i].x = group_index[j].x;
            }
            if (pick_beats(j, i, 1)) {
                group_picked[i].zw = group_picked[j].zw;
                group_length[i].y = group_length[j].y;
                group_index[i].y = group_index[j].y;
            }
        }
        barrier();
    }
    return group_picked[0];
}

// What the including pass defines: its scan, which offers the candidates first + step * (i, j)
// of `tile` in row-major order, and where a tile's pick goes.
void scan(ivec2 tile, ivec2 first, int step);
void store_pick(ivec2 tile, vec4 pick);

uniform bool group_per_tile;  // a work group per tile; else one invocation per tile

// The pass's main: picks for the tile this invocation (group) serves of a `grid`-sized output.
void pick_tiles(ivec2 grid) {
    if (!group_per_tile) {
        ivec2 tile = ivec2(gl_GlobalInvocationID.xy);
        if (any(greaterThanEqual(tile, grid))) return;
        scan(tile, ivec2(0), 1);
        store_pick(tile, picked);
        return;
    }
    // group_per_tile is a uniform: group_pick's barriers stay in uniform control flow.
    ivec2 tile = ivec2(gl_WorkGroupID.xy);
    scan(tile, ivec2(gl_LocalInvocationID.xy), PICK_GROUP_SIDE);
    vec4 best = group_pick();
    if (gl_LocalInvocationIndex == 0u) store_pick(tile, best);
}
