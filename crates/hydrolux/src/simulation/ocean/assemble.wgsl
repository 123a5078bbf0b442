// Unpack the transformed fields into the textures the surface is drawn from
// (layout in shaders/surface.wgsl).

struct AssembleParams {
    n: u32,
    cascades: u32,
    _pad0: u32,
    _pad1: u32,
}

@group(0) @binding(0) var<uniform> params: AssembleParams;
@group(0) @binding(1) var<storage, read> fields: array<vec4<f32>>;
@group(0) @binding(2) var displacement_out: texture_storage_2d_array<rgba16float, write>;
@group(0) @binding(3) var derivative_out: texture_storage_2d_array<rgba16float, write>;
@group(0) @binding(4) var moments_out: texture_storage_2d_array<rgba16float, write>;

@compute @workgroup_size(8, 8, 1)
fn assemble(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = params.n;
    if (id.x >= n || id.y >= n) {
        return;
    }
    let c = id.z;
    let i = id.y * n + id.x;
    // a = (Dx, h, Dz, ∂h/∂x), b = (∂h/∂z, ∂Dx/∂x, ∂Dz/∂z, ∂Dx/∂z)
    let a = fields[(2u * c) * n * n + i];
    let b = fields[(2u * c + 1u) * n * n + i];
    let p = vec2<i32>(id.xy);
    textureStore(displacement_out, p, c, vec4<f32>(a.x, a.y, a.z, b.w));
    textureStore(derivative_out, p, c, vec4<f32>(a.w, b.x, b.y, b.z));
    textureStore(moments_out, p, c, vec4<f32>(a.w * a.w, b.x * b.x, a.w * b.x, 0.0));
}
