//! The sea's BRDF where its waves are smaller than a pixel (seed 000 §5.2;
//! Bruneton, Neyret & Holzschuch 2010, *Real-time Realistic Ocean Lighting
//! using Seamless Transitions from Geometry to BRDF*).
//!
//! A pixel of distant sea holds many facets whose slopes ζ are Gaussian
//! about the pixel's mean slope, with the variance the filtered slope
//! moments resolve plus the unresolved (Cox–Munk) rest. Its mean radiance is
//! what those facets send, each weighted by the area it shows the eye:
//! - **the sun's glitter**: the microfacet BRDF of the slope distribution,
//!   E·F(v·h)·p(ζ_h) / (4 cos⁴θ_h cos θ_v), over the projected area of the
//!   pixel's mean surface, masked and shadowed by Smith's term for Gaussian
//!   slopes, 1 / (1 + Λ(v) + Λ(l)) (Bruneton's eq. 8);
//! - **the sky and the water body**: each visible facet reflects F(n·v) of the
//!   sky about its own normal and lets the rest through. A facet's share of
//!   the pixel is p(ζ)·(n·v)/n_y = p(ζ)·(v_y − ζ·v_xz): facets tilted towards
//!   the eye show more, those tilted away less or nothing. Fresnel grows
//!   fast at grazing angles, so F at the mean normal (the single facet the
//!   old far band used) overstates the reflection of a grazing distant sea;
//!   the mean over the visible facets is what a full-resolution rendering of
//!   the same sea averages to.
//!
//! Only the slope component along the view's azimuth moves n·v to first
//! order, so the shader ([`filtered_reflection`], `shaders/sea_brdf.wgsl`)
//! integrates the visible facets over that component with
//! [`REFLECTION_NODES`] midpoints and looks the sky up once, about the
//! Fresnel-weighted mean reflected direction, in the cube filtered for the
//! pixel's roughness. [`visible_mean_fresnel`] is the reference: the full
//! two-dimensional integral. The tests check both against a patch of the FFT
//! ocean ray-cast facet by facet.

use glam::DVec3;
use std::f64::consts::PI;

/// Midpoints of the shader's quadrature over the slope along the view.
pub const REFLECTION_NODES: usize = 8;
/// The quadrature spans the mean slope ± this many standard deviations.
pub const REFLECTION_SPAN: f64 = 3.0;

/// Gaussian slope statistics of the surface inside one pixel: the mean
/// slope (∂h/∂x, ∂h/∂z) and the variance along x and z.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SlopeStatistics {
    pub mean: [f64; 2],
    pub variance: [f64; 2],
}

impl SlopeStatistics {
    /// The mean surface's unit normal.
    pub fn mean_normal(&self) -> DVec3 {
        DVec3::new(-self.mean[0], 1.0, -self.mean[1]).normalize()
    }

    /// Slope variance along the horizontal unit direction `azimuth`
    /// (x and z slopes taken as uncorrelated, as the shader's moments are).
    pub fn variance_along(&self, azimuth: [f64; 2]) -> f64 {
        self.variance[0] * azimuth[0] * azimuth[0] + self.variance[1] * azimuth[1] * azimuth[1]
    }

    /// Probability density of slope ζ.
    pub fn density(&self, zeta: [f64; 2]) -> f64 {
        let v = [self.variance[0].max(1e-10), self.variance[1].max(1e-10)];
        let d = [zeta[0] - self.mean[0], zeta[1] - self.mean[1]];
        (-0.5 * (d[0] * d[0] / v[0] + d[1] * d[1] / v[1])).exp() / (2.0 * PI * (v[0] * v[1]).sqrt())
    }
}

/// The slope of the facet whose normal is `n`.
pub fn slope_of(n: DVec3) -> [f64; 2] {
    [-n.x / n.y, -n.z / n.y]
}

/// The horizontal unit direction of `d`, or x where `d` is vertical.
fn azimuth(d: DVec3) -> [f64; 2] {
    let s = (d.x * d.x + d.z * d.z).sqrt();
    if s < 1e-9 { [1.0, 0.0] } else { [d.x / s, d.z / s] }
}

/// Complementary error function (Abramowitz & Stegun 7.1.26, |ε| < 1.5e-7).
fn erfc(x: f64) -> f64 {
    if x < 0.0 {
        return 2.0 - erfc(-x);
    }
    let t = 1.0 / (1.0 + 0.327_591_1 * x);
    let poly = t
        * (0.254_829_592
            + t * (-0.284_496_736
                + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    poly * (-x * x).exp()
}

/// Smith's Λ for Gaussian slopes of standard deviation `sigma` along the
/// direction's azimuth, seen at `cos_theta` from the mean normal (exact:
/// Λ = (e^(−a²)/(a√π) − erfc a)/2 with a = cot θ / (√2 σ)).
pub fn smith_lambda(cos_theta: f64, sigma: f64) -> f64 {
    let c = cos_theta.clamp(1e-6, 1.0);
    let a = c / ((1.0 - c * c).sqrt().max(1e-12) * std::f64::consts::SQRT_2 * sigma.max(1e-9));
    if a > 8.0 {
        return 0.0;
    }
    (0.5 * ((-a * a).exp() / (a * PI.sqrt()) - erfc(a))).max(0.0)
}

/// The rational fit of Λ the shader evaluates (Walter et al. 2007, eq. 27,
/// written for Λ = 1/G₁ − 1; within 0.35% of G₁ everywhere).
pub fn smith_lambda_fit(cos_theta: f64, sigma: f64) -> f64 {
    let c = cos_theta.clamp(1e-6, 1.0);
    let a = c / ((1.0 - c * c).sqrt().max(1e-12) * std::f64::consts::SQRT_2 * sigma.max(1e-9));
    if a >= 1.6 {
        return 0.0;
    }
    (1.0 - 1.259 * a + 0.396 * a * a) / (3.535 * a + 2.181 * a * a)
}

/// Radiance of the sun's glitter per unit of the sun's (normal) irradiance:
/// `v` towards the eye, `l` towards the sun, `fresnel(cos)` the reflectance.
/// Bruneton et al.'s eq. 8 over the projected area of the pixel's mean
/// surface (which is tilted by the resolved waves), masked and shadowed.
pub fn sun_glitter(
    v: DVec3,
    l: DVec3,
    stats: &SlopeStatistics,
    fresnel: impl Fn(f64) -> f64,
) -> f64 {
    let n = stats.mean_normal();
    let (cos_v, cos_l) = (n.dot(v), n.dot(l));
    if l.y <= 0.0 || cos_l <= 0.0 || cos_v <= 0.0 {
        return 0.0;
    }
    let h = (v + l).normalize();
    let p = stats.density(slope_of(h));
    let sigma_v = stats.variance_along(azimuth(v)).sqrt();
    let sigma_l = stats.variance_along(azimuth(l)).sqrt();
    let masking = 1.0 + smith_lambda_fit(cos_v, sigma_v) + smith_lambda_fit(cos_l, sigma_l);
    fresnel(v.dot(h)) * p * n.y / (4.0 * h.y.powi(4) * cos_v * masking)
}

/// What the visible facets of a pixel reflect, as the shader integrates it:
/// their mean Fresnel reflectance and the direction about which the sky is
/// looked up (the Fresnel-weighted mean of their mirror directions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilteredReflection {
    pub fresnel: f64,
    pub direction: DVec3,
}

/// The shader's quadrature (`sea_reflection` in `shaders/sea_brdf.wgsl`):
/// [`REFLECTION_NODES`] midpoints over the slope along the view's azimuth,
/// from [`REFLECTION_SPAN`] σ below the mean to that far above it or to the
/// slope that turns a facet edge-on, each weighted by its density and the
/// area it shows the eye.
pub fn filtered_reflection(
    v: DVec3,
    stats: &SlopeStatistics,
    fresnel: impl Fn(f64) -> f64,
) -> FilteredReflection {
    let u = azimuth(v);
    let s = (v.x * v.x + v.z * v.z).sqrt();
    let mean_along = stats.mean[0] * u[0] + stats.mean[1] * u[1];
    let sigma = stats.variance_along(u).sqrt().max(1e-6);
    let across = stats.variance_along([-u[1], u[0]]);
    // Facets steeper than v_y / s along the view face away from the eye.
    let edge_on = if s > 1e-9 { v.y / s } else { f64::INFINITY };
    let lo = mean_along - REFLECTION_SPAN * sigma;
    let hi = (mean_along + REFLECTION_SPAN * sigma).min(edge_on);
    let mean_normal = stats.mean_normal();
    if hi <= lo {
        // Every facet faces away (the eye below the mean surface's horizon):
        // the mean normal's answer.
        let c = mean_normal.dot(v).max(0.0);
        return FilteredReflection { fresnel: fresnel(c), direction: (-v).reflect(mean_normal) };
    }
    let step = (hi - lo) / REFLECTION_NODES as f64;
    let (mut weight_sum, mut fresnel_sum, mut direction) = (0.0, 0.0, DVec3::ZERO);
    for i in 0..REFLECTION_NODES {
        let along = lo + (i as f64 + 0.5) * step;
        let d = (along - mean_along) / sigma;
        let weight = (-0.5 * d * d).exp() * (v.y - s * along).max(0.0);
        let slope = [
            stats.mean[0] + (along - mean_along) * u[0],
            stats.mean[1] + (along - mean_along) * u[1],
        ];
        // The slope across the view varies too: it tilts facets away from
        // the eye on both sides, which E[|n|²] carries.
        let tilted = DVec3::new(-slope[0], 1.0, -slope[1]);
        let n = tilted.normalize();
        let f = fresnel((tilted.dot(v) / (tilted.length_squared() + across).sqrt()).max(0.0));
        weight_sum += weight;
        fresnel_sum += weight * f;
        direction += weight * f * (-v).reflect(n);
    }
    FilteredReflection {
        fresnel: fresnel_sum / weight_sum.max(1e-30),
        direction: direction.try_normalize().unwrap_or_else(|| (-v).reflect(mean_normal)),
    }
}

/// The reference: the mean Fresnel reflectance over the pixel's visible
/// facets, integrated over both slope components on a fine grid (±5σ).
pub fn visible_mean_fresnel(
    v: DVec3,
    stats: &SlopeStatistics,
    fresnel: impl Fn(f64) -> f64,
) -> f64 {
    const STEPS: usize = 400;
    let sd = [stats.variance[0].sqrt().max(1e-6), stats.variance[1].sqrt().max(1e-6)];
    let (mut weight_sum, mut fresnel_sum) = (0.0, 0.0);
    for j in 0..STEPS {
        for i in 0..STEPS {
            let at = |k: usize, axis: usize| {
                stats.mean[axis] + sd[axis] * (-5.0 + 10.0 * (k as f64 + 0.5) / STEPS as f64)
            };
            let zeta = [at(i, 0), at(j, 1)];
            let n = DVec3::new(-zeta[0], 1.0, -zeta[1]).normalize();
            // The facet's projected area per unit of horizontal area.
            let shown = (v.y - zeta[0] * v.x - zeta[1] * v.z).max(0.0);
            let weight = stats.density(zeta) * shown;
            weight_sum += weight;
            fresnel_sum += weight * fresnel(n.dot(v).max(0.0));
        }
    }
    fresnel_sum / weight_sum.max(1e-30)
}

#[cfg(test)]
mod tests;
