// Fresnel reflectance. WGSL twin of hydrolux_core::optics (seed 000 §2.1.2, §3.2).

#import modes

// Exact unpolarized Fresnel reflectance, light arriving with cos_i from n1 into n2.
fn fresnel_exact(cos_i_in: f32, n1: f32, n2: f32) -> f32 {
    let cos_i = clamp(cos_i_in, 0.0, 1.0);
    let sin_t = n1 / n2 * sqrt(max(1.0 - cos_i * cos_i, 0.0));
    let cos_t = sqrt(max(1.0 - sin_t * sin_t, 0.0));
    let rs = (n1 * cos_i - n2 * cos_t) / max(n1 * cos_i + n2 * cos_t, 1e-12);
    let rp = (n1 * cos_t - n2 * cos_i) / max(n1 * cos_t + n2 * cos_i, 1e-12);
    // Branchless: total internal reflection beyond the critical angle (a
    // divergent early return here crashes Mesa's lavapipe in some shaders).
    return select(0.5 * (rs * rs + rp * rp), 1.0, sin_t >= 1.0);
}

// Schlick's approximation; leaving the denser medium it uses the transmitted angle.
fn fresnel_schlick(cos_i_in: f32, n1: f32, n2: f32) -> f32 {
    var c = clamp(cos_i_in, 0.0, 1.0);
    if (n1 > n2) {
        let sin_t2 = (n1 / n2) * (n1 / n2) * (1.0 - c * c);
        if (sin_t2 >= 1.0) {
            return 1.0;
        }
        c = sqrt(1.0 - sin_t2);
    }
    let r = (n1 - n2) / (n1 + n2);
    let r0 = r * r;
    return r0 + (1.0 - r0) * pow(1.0 - c, 5.0);
}

// cos θ for the approximations that only know external reflection: leaving
// the denser medium, the transmitted angle's; −1 beyond the critical angle.
fn external_cos(cos_i: f32, n1: f32, n2: f32) -> f32 {
    let c = clamp(cos_i, 0.0, 1.0);
    if (n1 <= n2) {
        return c;
    }
    let sin_t2 = (n1 / n2) * (n1 / n2) * (1.0 - c * c);
    if (sin_t2 >= 1.0) {
        return -1.0;
    }
    return sqrt(1.0 - sin_t2);
}

// Jensen & Goliáš: 1/(1 + cos θ)^8 (seed 003 eq. 27).
fn fresnel_jensen_golias(cos_i: f32, n1: f32, n2: f32) -> f32 {
    let c = external_cos(cos_i, n1, n2);
    if (c < 0.0) {
        return 1.0;
    }
    return 1.0 / pow(1.0 + c, 8.0);
}

// (1 − E·N)^q (seed 002 eq. 3).
fn fresnel_power(cos_i: f32, n1: f32, n2: f32, q: f32) -> f32 {
    let c = external_cos(cos_i, n1, n2);
    if (c < 0.0) {
        return 1.0;
    }
    return pow(max(1.0 - c, 0.0), q);
}

// mode: 0 exact, 1 Schlick, 2 Jensen–Goliáš, 3 power (exponent q).
fn fresnel(mode: u32, q: f32, cos_i: f32, n1: f32, n2: f32) -> f32 {
    switch (mode) {
        case FRESNEL_SCHLICK: { return fresnel_schlick(cos_i, n1, n2); }
        case FRESNEL_JENSEN_GOLIAS: { return fresnel_jensen_golias(cos_i, n1, n2); }
        case FRESNEL_POWER: { return fresnel_power(cos_i, n1, n2, q); }
        default: { return fresnel_exact(cos_i, n1, n2); }
    }
}
