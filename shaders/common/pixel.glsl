// Pixel conventions, docs/spec.md §1: texel (x, y) is image pixel (x, y), x right, y down, row 0 at
// the top (textures are stored top row first; see src/gl/texture.h); its center is (x+0.5, y+0.5).

// Nearest pixel inside the image: the default edge rule ("clamp").
ivec2 clamp_to_image(ivec2 p, ivec2 size) {
    return clamp(p, ivec2(0), size - 1);
}

bool outside(ivec2 p, ivec2 size) {
    return any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size));
}
