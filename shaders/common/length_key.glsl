// What TileMax and NeighborMax compare a half-vector's length as (docs/spec.md §17.10): the
// length itself, or with LENGTH_KEY_STEPS defined, floor(length · steps + 1/4), so that lengths
// within one 1/steps px step tie and go to the first candidate in row order. engine_godot asks
// for it: its velocities clamped to the tile size are equal lengths that float32 rounding would
// otherwise order at random. The quarter step keeps whole and half pixels (the clamps) off a
// step's edge. NumPy twin: blurlab.twins.mcguire2012.length_key.
#ifndef LENGTH_KEY_INCLUDED
#define LENGTH_KEY_INCLUDED
float length_key(float len) {
#ifdef LENGTH_KEY_STEPS
    return floor(len * float(LENGTH_KEY_STEPS) + 0.25);
#else
    return len;
#endif
}
#endif
