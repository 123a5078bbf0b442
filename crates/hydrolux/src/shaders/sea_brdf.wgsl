// The sea's BRDF where its waves are smaller than a pixel (seed 000 §5.2;
// Bruneton, Neyret & Holzschuch 2010): the pixel's facets have Gaussian
// slopes about its mean slope, with the variance the filtered moments
// resolve plus the unresolved rest. CPU twin and the reasoning:
// hydrolux_core::waves::sea_brdf (tested there against a ray-cast patch of
// the FFT ocean). Needs `optics` (fresnel) and `constants`.

// Midpoints of the quadrature over the slope along the view (REFLECTION_NODES
// and REFLECTION_SPAN in the twin).
const SEA_REFLECTION_NODES: u32 = 8u;
const SEA_REFLECTION_SPAN: f32 = 3.0;

// Probability density of slope `zeta` about `mean` (per-axis variance).
fn slope_pdf(zeta: vec2<f32>, mean: vec2<f32>, variance: vec2<f32>) -> f32 {
    let v = max(variance, vec2<f32>(1e-10));
    let d = zeta - mean;
    return exp(-0.5 * (d.x * d.x / v.x + d.y * d.y / v.y)) / (TAU * sqrt(v.x * v.y));
}

// The horizontal unit direction of `d` (x where `d` is vertical).
fn sea_azimuth(d: vec3<f32>) -> vec2<f32> {
    let s = length(d.xz);
    return select(vec2<f32>(1.0, 0.0), d.xz / max(s, 1e-9), s > 1e-6);
}

// Smith's Λ for Gaussian slopes of deviation `sigma`, seen at `cos_theta`
// from the mean normal: Walter et al.'s rational fit (2007, eq. 27).
fn smith_lambda_fit(cos_theta: f32, sigma: f32) -> f32 {
    let c = clamp(cos_theta, 1e-6, 1.0);
    let a = c / (max(sqrt(1.0 - c * c), 1e-12) * 1.41421356 * max(sigma, 1e-9));
    let lambda = (1.0 - 1.259 * a + 0.396 * a * a) / (3.535 * a + 2.181 * a * a);
    return select(lambda, 0.0, a >= 1.6);
}

// The sun's glitter per unit of its normal irradiance (Bruneton et al.'s
// eq. 8 over the projected area of the pixel's mean surface, masked and
// shadowed): `v` towards the eye, `l` towards the sun.
fn sea_glitter(v: vec3<f32>, l: vec3<f32>, mean: vec2<f32>, variance: vec2<f32>, mode: u32, q: f32, ior: f32) -> f32 {
    let n = normalize(vec3<f32>(-mean.x, 1.0, -mean.y));
    let cos_v = dot(n, v);
    let cos_l = dot(n, l);
    let h = normalize(v + l);
    let p = slope_pdf(-h.xz / max(h.y, 1e-6), mean, variance);
    let sigma_v = sqrt(dot(variance, sea_azimuth(v) * sea_azimuth(v)));
    let sigma_l = sqrt(dot(variance, sea_azimuth(l) * sea_azimuth(l)));
    let masking = 1.0 + smith_lambda_fit(cos_v, sigma_v) + smith_lambda_fit(cos_l, sigma_l);
    let f = fresnel(mode, q, dot(v, h), 1.0, ior);
    let glitter = f * p * n.y / (4.0 * pow(max(h.y, 1e-6), 4.0) * max(cos_v, 1e-6) * masking);
    return select(0.0, glitter, l.y > 0.0 && cos_l > 0.0 && cos_v > 0.0);
}

// What a pixel's visible facets reflect: their mean Fresnel reflectance and
// the Fresnel-weighted mean of their mirror directions (about which the
// filtered sky is looked up).
struct SeaReflection {
    fresnel: f32,
    direction: vec3<f32>,
}

// Midpoints over the slope along the view's azimuth, ±SPAN σ about the mean
// or up to the slope that turns a facet edge-on, each weighted by its
// density and by the area it shows the eye (v_y − s·ζ).
fn sea_reflection(v: vec3<f32>, mean: vec2<f32>, variance: vec2<f32>, mode: u32, q: f32, ior: f32) -> SeaReflection {
    let u = sea_azimuth(v);
    let s = length(v.xz);
    let mean_along = dot(mean, u);
    let sigma = max(sqrt(dot(variance, u * u)), 1e-6);
    let across = dot(variance, vec2<f32>(u.y * u.y, u.x * u.x));
    let edge_on = select(1e30, v.y / max(s, 1e-9), s > 1e-9);
    let lo = mean_along - SEA_REFLECTION_SPAN * sigma;
    let hi = min(mean_along + SEA_REFLECTION_SPAN * sigma, edge_on);
    let mean_normal = normalize(vec3<f32>(-mean.x, 1.0, -mean.y));
    if (hi <= lo) {
        // Every facet faces away: the mean normal's answer.
        let f = fresnel(mode, q, max(dot(mean_normal, v), 0.0), 1.0, ior);
        return SeaReflection(f, reflect(-v, mean_normal));
    }
    let step = (hi - lo) / f32(SEA_REFLECTION_NODES);
    var weight_sum = 0.0;
    var fresnel_sum = 0.0;
    var direction = vec3<f32>(0.0);
    for (var i = 0u; i < SEA_REFLECTION_NODES; i++) {
        let along = lo + (f32(i) + 0.5) * step;
        let d = (along - mean_along) / sigma;
        let weight = exp(-0.5 * d * d) * max(v.y - s * along, 0.0);
        let slope = mean + (along - mean_along) * u;
        // The slope across the view tilts facets away on both sides: E[|n|²].
        let tilted = vec3<f32>(-slope.x, 1.0, -slope.y);
        let n = normalize(tilted);
        let f = fresnel(mode, q, max(dot(tilted, v) / sqrt(dot(tilted, tilted) + across), 0.0), 1.0, ior);
        weight_sum += weight;
        fresnel_sum += weight * f;
        direction += weight * f * reflect(-v, n);
    }
    let fallback = reflect(-v, mean_normal);
    let len = length(direction);
    return SeaReflection(fresnel_sum / max(weight_sum, 1e-30), select(fallback, direction / max(len, 1e-30), len > 1e-20));
}
