// The error view (`render.view = "error"`, issue #16's truth mode): per
// pixel the CIELAB colour difference ΔE*ab between the frame as the
// projective approximations draw it and as ray tracing does, both as
// displayed (tone mapped, 8-bit sRGB), as a heat ramp: black 0, red 10,
// yellow 20, white 40. Twin: hydrolux-core compare (srgb8_to_lab, delta_e,
// heat). SRGB_TARGET (prepended): the images and the target are an sRGB
// format (loads decode, stores encode), else they hold the encoded values.
#import fullscreen, tonemap_curve

@group(0) @binding(0) var projective_image: texture_2d<f32>;
@group(0) @binding(1) var traced_image: texture_2d<f32>;

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(fullscreen_ndc(i), 0.0, 1.0);
}

fn srgb_to_linear(c: vec3<f32>) -> vec3<f32> {
    let lo = c / 12.92;
    let hi = pow((c + 0.055) / 1.055, vec3<f32>(2.4));
    return select(hi, lo, c <= vec3<f32>(0.04045));
}

fn lab_f(t: f32) -> f32 {
    let d = 6.0 / 29.0;
    if (t > d * d * d) {
        return pow(t, 1.0 / 3.0);
    }
    return t / (3.0 * d * d) + 4.0 / 29.0;
}

// CIELAB of a linear sRGB colour (D65 white).
fn lab(lin: vec3<f32>) -> vec3<f32> {
    let x = dot(vec3<f32>(0.4124, 0.3576, 0.1805), lin);
    let y = dot(vec3<f32>(0.2126, 0.7152, 0.0722), lin);
    let z = dot(vec3<f32>(0.0193, 0.1192, 0.9505), lin);
    let fx = lab_f(x / 0.95047);
    let fy = lab_f(y);
    let fz = lab_f(z / 1.08883);
    return vec3<f32>(116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz));
}

// The displayed colour's linear value, quantised to 8 bits as the CPU's
// images are.
fn displayed_linear(loaded: vec3<f32>) -> vec3<f32> {
    var encoded = loaded;
    if (SRGB_TARGET) {
        encoded = linear_to_srgb(loaded);
    }
    return srgb_to_linear(round(clamp(encoded, vec3<f32>(0.0), vec3<f32>(1.0)) * 255.0) / 255.0);
}

@fragment
fn fs_main(@builtin(position) frag: vec4<f32>) -> @location(0) vec4<f32> {
    let p = vec2<i32>(frag.xy);
    let a = lab(displayed_linear(textureLoad(projective_image, p, 0).rgb));
    let b = lab(displayed_linear(textureLoad(traced_image, p, 0).rgb));
    let e = distance(a, b);
    let heat = clamp((vec3<f32>(e) - vec3<f32>(0.0, 10.0, 20.0)) / vec3<f32>(10.0, 10.0, 20.0), vec3<f32>(0.0), vec3<f32>(1.0));
    if (SRGB_TARGET) {
        return vec4<f32>(srgb_to_linear(heat), 1.0);
    }
    return vec4<f32>(heat, 1.0);
}
