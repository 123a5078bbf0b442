// Time evolution of the initial spectrum h0 (Tessendorf §3.4) and the
// spectral fields for displacement, slopes and the Jacobian, packed two real
// fields per complex number. Twin: hydrolux_core::waves::ocean::evolve_mode.
#import constants, complex

struct SpectrumMode {
    h0: vec2<f32>,
    h0_minus_conj: vec2<f32>,
    kx: f32,
    kz: f32,
    omega_cycles: u32,
    _pad: u32,
}

struct EvolveParams {
    // Time phase τ = frac(t/T)·2³², FFT size N, cascades; choppiness λ.
    phase: u32,
    n: u32,
    cascades: u32,
    choppiness: f32,
}

@group(0) @binding(0) var<uniform> params: EvolveParams;
@group(0) @binding(1) var<storage, read> modes: array<SpectrumMode>;
@group(0) @binding(2) var<storage, read_write> fields: array<vec4<f32>>;

@compute @workgroup_size(8, 8, 1)
fn evolve(@builtin(global_invocation_id) id: vec3<u32>) {
    let n = params.n;
    if (id.x >= n || id.y >= n) {
        return;
    }
    let c = id.z;
    let i = id.y * n + id.x;
    let m = modes[c * n * n + i];
    // Exact phase: whole cycles × τ wraps mod 2³², i.e. mod one period.
    let turns = m.omega_cycles * params.phase;
    let theta = f32(turns) * (TAU / 4294967296.0);
    let h = cmul(m.h0, cexp_i(-theta)) + cmul(m.h0_minus_conj, cexp_i(theta));
    let kv = vec2<f32>(m.kx, m.kz);
    let k = length(kv);
    var inv_k = 0.0;
    if (k > 0.0) {
        inv_k = 1.0 / k;
    }
    // D = +i·λ·(k/|k|)·h̃: with the e^(+ik·x) sum this moves points towards
    // the crests (Gerstner's x₀ − Q·k̂·A·sin θ), so crests sharpen and fold.
    let lambda = params.choppiness;
    let dx = cmul_i(h * (lambda * kv.x * inv_k));
    let dz = cmul_i(h * (lambda * kv.y * inv_k));
    let hx = cmul_i(h * kv.x);
    let hz = cmul_i(h * kv.y);
    let dxx = h * (-lambda * kv.x * kv.x * inv_k);
    let dzz = h * (-lambda * kv.y * kv.y * inv_k);
    let dxz = h * (-lambda * kv.x * kv.y * inv_k);
    // A + i·B for complex A, B.
    let f0 = dx + cmul_i(h);
    let f1 = dz + cmul_i(hx);
    let f2 = hz + cmul_i(dxx);
    let f3 = dzz + cmul_i(dxz);
    let plane = n * n;
    fields[(2u * c) * plane + i] = vec4<f32>(f0, f1);
    fields[(2u * c + 1u) * plane + i] = vec4<f32>(f2, f3);
}
