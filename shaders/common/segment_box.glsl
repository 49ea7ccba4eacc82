// Whether the segment start + t·d, t in [0, 1], meets the square [low, high]² (the slab test; a
// zero component must lie inside its slab). Used by the tile dilations of engine_eevee and
// engine_hdrp (docs/spec.md §17.2, §17.4). NumPy twin: blurlab.twins.eevee.segment_meets_box.
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
