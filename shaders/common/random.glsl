// Hashed random numbers, docs/spec.md §1 "Random numbers". Same inputs, same bits, on every device.
// NumPy twin: blurlab.twins.hashing.

uint pcg(uint v) {
    uint s = v * 747796405u + 2891336453u;
    uint w = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return (w >> 22u) ^ w;
}

// rand(x, y, seed) = pcg(x ^ pcg(y ^ pcg(seed))) / 2^32, in [0, 1). Only the top 24 bits are
// kept: float(u) / 2^32 would round the largest u up to 1.0 in float32.
float rand(uint x, uint y, uint seed) {
    uint u = pcg(x ^ pcg(y ^ pcg(seed)));
    return float(u >> 8u) * (1.0 / 16777216.0);
}
