// Whether a tile's motion reaches another tile (docs/spec.md §17.2 step 2, §17.5 step 3): the
// motion's segment, in tile units, meets the other tile's square widened by how far a tile's
// pixel centers lie from its center, h = 1/2 - 1/(2s), plus REACH_MARGIN against rounding.
// Shared by engine_eevee's dilation and engine_unreal's 7 x 7 neighbourhood.
// NumPy twin: blurlab.twins.tile_reach.

const float REACH_MARGIN = 0.01;  // tiles added around a tile's reach

// h + REACH_MARGIN for tiles of `tile_size` pixels.
float reach_widening(int tile_size) {
    return 0.5 - 0.5 / float(tile_size) + REACH_MARGIN;
}

// Whether start + t·d, t in [0, 1], meets the square [low, high]² (the slab test).
bool segment_meets_box(vec2 start, vec2 d, float low, float high) {
    float t_min = 0.0, t_max = 1.0;
    for (int axis = 0; axis < 2; ++axis) {
        float p = start[axis];
        if (d[axis] == 0.0) {
            if (p < low || p > high) return false;
            continue;
        }
        float t1 = (low - p) / d[axis];
        float t2 = (high - p) / d[axis];
        t_min = max(t_min, min(t1, t2));
        t_max = min(t_max, max(t1, t2));
    }
    return t_min <= t_max;
}
