// Inverse FFT along rows or columns: one workgroup transforms one line of N
// vec4 (two complex numbers each) in workgroup memory, radix-2 decimation in
// time after a bit-reversed load. FFT_N, FFT_LOG2_N and FFT_THREADS are
// prepended by the pipeline (src/simulation/ocean/mod.rs). Unnormalised, e^(+i):
// the plain sum h(x) = Σ h̃(k)·e^(ik·x), as rustfft's inverse transform.
#import constants, complex

@group(0) @binding(0) var<storage, read_write> lines: array<vec4<f32>>;

var<workgroup> line: array<vec4<f32>, FFT_N>;

fn transform(base: u32, stride: u32, lid: u32) {
    for (var i = lid; i < FFT_N; i += FFT_THREADS) {
        let r = reverseBits(i) >> (32u - FFT_LOG2_N);
        line[r] = lines[base + i * stride];
    }
    workgroupBarrier();
    for (var s = 0u; s < FFT_LOG2_N; s++) {
        let half = 1u << s;
        for (var b = lid; b < FFT_N / 2u; b += FFT_THREADS) {
            let j = b & (half - 1u);
            let i0 = ((b >> s) << (s + 1u)) + j;
            let i1 = i0 + half;
            let w = cexp_i(PI * f32(j) / f32(half));
            let lo = line[i0];
            let hi = line[i1];
            let t = vec4<f32>(cmul(w, hi.xy), cmul(w, hi.zw));
            line[i0] = lo + t;
            line[i1] = lo - t;
        }
        workgroupBarrier();
    }
    for (var i = lid; i < FFT_N; i += FFT_THREADS) {
        lines[base + i * stride] = line[i];
    }
}

// workgroup (row, plane)
@compute @workgroup_size(FFT_THREADS, 1, 1)
fn fft_rows(@builtin(workgroup_id) wg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    transform(wg.y * FFT_N * FFT_N + wg.x * FFT_N, 1u, lid);
}

// workgroup (column, plane)
@compute @workgroup_size(FFT_THREADS, 1, 1)
fn fft_columns(@builtin(workgroup_id) wg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    transform(wg.y * FFT_N * FFT_N + wg.x, FFT_N, lid);
}
