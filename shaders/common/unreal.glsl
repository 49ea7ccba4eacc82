// What engine_unreal's passes share (docs/spec.md §17.5): the tile size, the neighbourhood's
// reach and the tile classes. NumPy twin: blurlab.twins.unreal.

const int TILE = 16;                // tile side, pixels
const int NEIGHBORHOOD_REACH = 3;   // the 7 x 7 tiles around a tile
const float SKIP_BELOW = 0.5;       // px: a tile whose longest reaching velocity is shorter keeps C
const float TILE_SKIP = 0.0, TILE_FAST = 1.0, TILE_SLOW = 2.0;
