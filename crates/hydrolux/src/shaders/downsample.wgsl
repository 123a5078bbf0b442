// One mip level of a 2D array texture from the level above: a 2×2 box filter
// (power-of-two sizes, so it is exact averaging; linear moments stay exact).

// The level above, read as a storage image (on GL a cube map has no sampled
// array view, see passes/mips.rs).
@group(0) @binding(0) var src: texture_storage_2d_array<rgba16float, read>;
@group(0) @binding(1) var dst: texture_storage_2d_array<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn downsample(@builtin(global_invocation_id) id: vec3<u32>) {
    let size = textureDimensions(dst);
    if (id.x >= size.x || id.y >= size.y) {
        return;
    }
    let p = vec2<i32>(id.xy) * 2;
    let layer = i32(id.z);
    let sum = textureLoad(src, p, layer) + textureLoad(src, p + vec2<i32>(1, 0), layer)
        + textureLoad(src, p + vec2<i32>(0, 1), layer) + textureLoad(src, p + vec2<i32>(1, 1), layer);
    textureStore(dst, vec2<i32>(id.xy), layer, sum * 0.25);
}
