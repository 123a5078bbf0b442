//! The opaque surfaces' specular reflection (issue #32 item 1): a
//! microfacet BRDF — Trowbridge–Reitz (GGX) normals, Smith's
//! height-correlated masking, Schlick's Fresnel (Walter et al., *Microfacet
//! Models for Refraction through Rough Surfaces*, EGSR 2007; Heitz,
//! *Understanding the Masking-Shadowing Function*, JCGT 2014) — lit by the
//! sun and by the sky's cube map filtered for the roughness, weighted by the
//! split sum's directional albedo (Karis, *Real Shading in Unreal Engine 4*,
//! 2013: a table integrated once). The diffuse part
//! keeps what the specular part does not take. Metals reflect in their
//! base colour and have no diffuse part. Fresnel's grazing reflectance f90
//! fades out for F0 below 2% (Schüler's specular occlusion, as Filament
//! does), so `specular = 0` is a pure Lambertian surface. WGSL twin:
//! `shaders/pbr.wgsl`; the cube's filtering: `passes/sky/prefilter.wgsl`.

use glam::Vec3;
use std::f32::consts::PI;

/// The narrowest lobe allowed (perceptual roughness): a mirror's GGX is a
/// delta the sun's disc and the cube's texels cannot resolve.
pub const MIN_ROUGHNESS: f32 = 0.02;

/// A surface's specular parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    pub base_color: Vec3,
    /// Perceptual roughness r; GGX's α = r².
    pub roughness: f32,
    pub metalness: f32,
    /// Reflectance at normal incidence of a dielectric: F0 = 0.08·specular
    /// (0.5 gives 0.04, glass and water's 0.02–0.04 and most paints').
    pub specular: f32,
}

impl Surface {
    /// Reflectance at normal incidence: the dielectric's grey F0, or the
    /// metal's base colour.
    pub fn f0(&self) -> Vec3 {
        Vec3::splat(0.08 * self.specular).lerp(self.base_color, self.metalness)
    }

    /// Reflectance at grazing incidence: 1, faded out below F0 = 2%.
    pub fn f90(&self) -> f32 {
        let f0 = self.f0();
        (50.0 * (f0.x + f0.y + f0.z) / 3.0).clamp(0.0, 1.0)
    }

    pub fn alpha(&self) -> f32 {
        let r = self.roughness.max(MIN_ROUGHNESS);
        r * r
    }
}

/// GGX's distribution of normals D(h) for α, at cos θh = `n_h`.
pub fn ggx(n_h: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let d = n_h * n_h * (a2 - 1.0) + 1.0;
    a2 / (PI * d * d)
}

/// Smith's height-correlated masking–shadowing over 4·(n·l)(n·v): the
/// "visibility" term V = G2 / (4 n·l n·v).
pub fn smith_visibility(n_v: f32, n_l: f32, alpha: f32) -> f32 {
    let a2 = alpha * alpha;
    let gv = n_l * (n_v * n_v * (1.0 - a2) + a2).sqrt();
    let gl = n_v * (n_l * n_l * (1.0 - a2) + a2).sqrt();
    0.5 / (gv + gl).max(1e-7)
}

pub fn fresnel_schlick(f0: Vec3, f90: f32, cos: f32) -> Vec3 {
    f0 + (Vec3::splat(f90) - f0) * (1.0 - cos.clamp(0.0, 1.0)).powi(5)
}

/// The specular BRDF f(l, v) for unit vectors n, l, v.
pub fn specular_brdf(s: &Surface, n: Vec3, l: Vec3, v: Vec3) -> Vec3 {
    let (n_l, n_v) = (n.dot(l), n.dot(v));
    if n_l <= 0.0 || n_v <= 0.0 {
        return Vec3::ZERO;
    }
    let h = (l + v).normalize();
    let a = s.alpha();
    fresnel_schlick(s.f0(), s.f90(), v.dot(h)) * ggx(n.dot(h), a) * smith_visibility(n_v, n_l, a)
}

/// Edge of the split sum's table (n·v across, roughness up).
pub const ENVIRONMENT_TABLE_SIZE: usize = 32;
/// GGX half vectors per texel of the table (a Hammersley set).
const ENVIRONMENT_SAMPLES: u32 = 512;

/// The split sum's scale and bias at (n·v, roughness): ∫ f·cos over the
/// hemisphere for a white sky is F0·scale + f90·bias. Integrated by GGX
/// importance sampling (Karis 2013, with this module's height-correlated
/// Smith term, so the table agrees with [`specular_brdf`]).
pub fn environment_brdf(n_v: f32, roughness: f32) -> (f32, f32) {
    let n_v = n_v.clamp(1e-3, 1.0);
    let v = Vec3::new((1.0 - n_v * n_v).sqrt(), n_v, 0.0);
    let r = roughness.max(MIN_ROUGHNESS);
    let alpha = r * r;
    let (mut scale, mut bias) = (0.0, 0.0);
    for i in 0..ENVIRONMENT_SAMPLES {
        let (u, w) = hammersley(i, ENVIRONMENT_SAMPLES);
        // A half vector drawn from D(h)·(n·h).
        let cos_h = ((1.0 - u) / (1.0 + (alpha * alpha - 1.0) * u)).sqrt();
        let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
        let phi = 2.0 * PI * w;
        let h = Vec3::new(sin_h * phi.cos(), cos_h, sin_h * phi.sin());
        let v_h = v.dot(h);
        let l = 2.0 * v_h * h - v;
        if l.y <= 0.0 || v_h <= 0.0 {
            continue;
        }
        // f·cos / pdf(l) with pdf(l) = D·(n·h) / (4·v·h).
        let weight = smith_visibility(n_v, l.y, alpha) * l.y * 4.0 * v_h / cos_h;
        let fc = (1.0 - v_h).powi(5);
        scale += (1.0 - fc) * weight;
        bias += fc * weight;
    }
    (scale / ENVIRONMENT_SAMPLES as f32, bias / ENVIRONMENT_SAMPLES as f32)
}

/// The split sum's table: texel (i, j) holds (scale, bias) at n·v =
/// (i + ½)/size and roughness (j + ½)/size, read bilinearly.
pub fn environment_table() -> Vec<[f32; 2]> {
    let n = ENVIRONMENT_TABLE_SIZE;
    (0..n * n)
        .map(|k| {
            let (i, j) = (k % n, k / n);
            let (s, b) = environment_brdf((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
            [s, b]
        })
        .collect()
}

/// The fraction of a uniform white sky a surface reflects specularly
/// towards v: its specular directional albedo (the split sum's second
/// factor).
pub fn specular_albedo(s: &Surface, n_v: f32) -> Vec3 {
    let (scale, bias) = environment_brdf(n_v, s.roughness);
    s.f0() * scale + Vec3::splat(s.f90() * bias)
}

/// The table as the GPU holds it (`EnvironmentBrdf` in a uniform buffer):
/// two texels per vec4, row by row.
pub fn environment_table_packed() -> Vec<[f32; 4]> {
    environment_table().chunks(2).map(|p| [p[0][0], p[0][1], p[1][0], p[1][1]]).collect()
}

/// The table read as the GPU reads it: bilinear between texel centres,
/// clamped at the edges.
pub fn environment_lookup(table: &[[f32; 2]], n_v: f32, roughness: f32) -> (f32, f32) {
    let n = ENVIRONMENT_TABLE_SIZE;
    let at = |x: f32| {
        let t = (x.clamp(0.0, 1.0) * n as f32 - 0.5).clamp(0.0, (n - 1) as f32);
        let i = (t.floor() as usize).min(n - 2);
        (i, t - i as f32)
    };
    let ((i, fx), (j, fy)) = (at(n_v), at(roughness));
    let texel = |i: usize, j: usize| table[j * n + i];
    let lerp =
        |a: [f32; 2], b: [f32; 2], t: f32| [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t];
    let r = lerp(
        lerp(texel(i, j), texel(i + 1, j), fx),
        lerp(texel(i, j + 1), texel(i + 1, j + 1), fx),
        fy,
    );
    (r[0], r[1])
}

/// What the diffuse part keeps: none of a metal; of a dielectric, what its
/// specular reflection does not take.
pub fn diffuse_weight(s: &Surface, n_v: f32) -> Vec3 {
    (Vec3::ONE - specular_albedo(s, n_v)) * (1.0 - s.metalness)
}

/// What a surface sends towards v from its environment: its diffuse part
/// of the irradiance `irradiance` on n, and its specular part of the
/// environment filtered for its roughness about the mirror direction
/// (`prefiltered_r`). As `environment_light` in pbr.wgsl.
pub fn environment_radiance(s: &Surface, n_v: f32, irradiance: Vec3, prefiltered_r: Vec3) -> Vec3 {
    s.base_color * diffuse_weight(s, n_v) * irradiance / PI
        + prefiltered_r * specular_albedo(s, n_v)
}

/// Mip levels of the sky cube that hold the specular lobes: level k is the
/// sky filtered for roughness k / (SPECULAR_LEVELS − 1); 128² down to 8²
/// (smaller levels would lose the lobe's direction). Levels past them hold
/// roughness 1 again.
pub const SPECULAR_LEVELS: u32 = 5;
/// GGX directions per texel of the first filtered level (a Hammersley set;
/// [`prefilter_samples`]).
pub const PREFILTER_SAMPLES: u32 = 64;

/// The mip level whose filtered radiance stands for the lobe of
/// `roughness`: linear in perceptual roughness.
pub fn cube_level(roughness: f32) -> f32 {
    roughness.clamp(0.0, 1.0) * (SPECULAR_LEVELS - 1) as f32
}

/// The roughness level `level` of the sky cube is filtered for.
pub fn level_roughness(level: u32) -> f32 {
    (level as f32 / (SPECULAR_LEVELS - 1) as f32).min(1.0)
}

/// Point `i` of the N-point Hammersley set: (i + ½)/N and the radical
/// inverse of i.
fn hammersley(i: u32, n: u32) -> (f32, f32) {
    ((i as f32 + 0.5) / n as f32, i.reverse_bits() as f32 / 4_294_967_296.0)
}

/// A GGX half vector of α about the normal n, drawn from D(h)·(n·h) by (u, w).
fn ggx_half(n: Vec3, alpha: f32, u: f32, w: f32) -> Vec3 {
    let cos_h = ((1.0 - u) / (1.0 + (alpha * alpha - 1.0) * u)).sqrt();
    let sin_h = (1.0 - cos_h * cos_h).max(0.0).sqrt();
    let phi = 2.0 * PI * w;
    let t = if n.y.abs() < 0.999 { Vec3::Y.cross(n).normalize() } else { Vec3::X };
    let b = n.cross(t);
    (t * (sin_h * phi.cos()) + b * (sin_h * phi.sin()) + n * cos_h).normalize()
}

/// GGX directions per texel of filtered level `level`: PREFILTER_SAMPLES
/// at level 1, doubled per level (the smaller levels' wider lobes see more
/// of the sky; their texels are few), at most 1024.
pub fn prefilter_samples(level: u32) -> u32 {
    (PREFILTER_SAMPLES << level.saturating_sub(1).min(4)).min(1024)
}

/// The environment `radiance` as level `level` of the sky cube holds it:
/// filtered for the specular lobe of [`level_roughness`] about direction
/// `r` (Karis 2013: the lobe with n = v = r, weighted by n·l), with the
/// same Hammersley set as the GPU's filter.
pub fn prefiltered(radiance: impl Fn(Vec3) -> Vec3, r: Vec3, level: u32) -> Vec3 {
    let roughness = level_roughness(level);
    if roughness <= 0.0 {
        return radiance(r);
    }
    let alpha = roughness * roughness;
    let samples = prefilter_samples(level);
    let (mut sum, mut weight) = (Vec3::ZERO, 0.0);
    for i in 0..samples {
        let (u, w) = hammersley(i, samples);
        let h = ggx_half(r, alpha, u, w);
        let l = 2.0 * r.dot(h) * h - r;
        let n_l = r.dot(l);
        if n_l > 0.0 {
            sum += radiance(l) * n_l;
            weight += n_l;
        }
    }
    sum / weight.max(1e-6)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hemisphere in θ × φ cells (midpoint rule).
    fn hemisphere(n: usize) -> impl Iterator<Item = (Vec3, f32)> {
        (0..n).flat_map(move |i| {
            // Cells crowd towards the pole, where a narrow lobe lives.
            let (u0, u1) = (i as f32 / n as f32, (i + 1) as f32 / n as f32);
            let (t0, t1) = (u0 * u0 * PI / 2.0, u1 * u1 * PI / 2.0);
            let theta = 0.5 * (t0 + t1);
            let d_omega = (t0.cos() - t1.cos()) * 2.0 * PI / (2 * n) as f32;
            (0..2 * n).map(move |j| {
                let phi = (j as f32 + 0.5) / (2 * n) as f32 * 2.0 * PI;
                (Vec3::new(theta.sin() * phi.cos(), theta.cos(), theta.sin() * phi.sin()), d_omega)
            })
        })
    }

    #[test]
    fn ggx_projects_to_one_over_the_hemisphere() {
        for alpha in [0.05f32, 0.2, 0.5, 1.0] {
            let total: f32 = hemisphere(400).map(|(h, dw)| ggx(h.y, alpha) * h.y * dw).sum();
            assert!((total - 1.0).abs() < 0.01, "α {alpha}: ∫D cos = {total}");
        }
    }

    #[test]
    fn the_brdf_is_reciprocal_and_white_furnace_bounded() {
        let s = Surface { base_color: Vec3::ONE, roughness: 0.6, metalness: 1.0, specular: 0.5 };
        let (l, v) = (Vec3::new(0.3, 0.8, 0.1).normalize(), Vec3::new(-0.5, 0.4, 0.2).normalize());
        let (a, b) = (specular_brdf(&s, Vec3::Y, l, v), specular_brdf(&s, Vec3::Y, v, l));
        assert!((a - b).abs().max_element() < 1e-6, "{a} vs {b}");
        // A white metal reflects at most everything (Smith's single
        // scattering loses some at high roughness, never gains).
        for n_v in [0.1f32, 0.5, 1.0] {
            let v = Vec3::new((1.0 - n_v * n_v).sqrt(), n_v, 0.0);
            let e = directional_albedo(&s, v);
            assert!(e.x <= 1.001 && e.x > 0.7, "n·v {n_v}: {e}");
        }
    }

    /// ∫ f(l, v)·(n·l) dω_l over a white sky, integrated over half vectors
    /// (dω_l = 4·(v·h)·dω_h), where the lobe's cells crowd whatever the
    /// view.
    fn directional_albedo(s: &Surface, v: Vec3) -> Vec3 {
        hemisphere(400)
            .map(|(h, dw)| {
                let l = 2.0 * v.dot(h) * h - v;
                if l.y <= 0.0 || v.dot(h) <= 0.0 {
                    return Vec3::ZERO;
                }
                specular_brdf(s, Vec3::Y, l, v) * l.y * 4.0 * v.dot(h) * dw
            })
            .sum()
    }

    /// The split sum's importance-sampled directional albedo against
    /// integrating the BRDF over a white sky on a grid, for a dielectric and
    /// a metal at several roughnesses and view angles.
    #[test]
    fn the_split_sum_table_matches_integration() {
        let mut worst = 0.0f32;
        for roughness in [0.1f32, 0.3, 0.5, 0.8, 1.0] {
            for metalness in [0.0f32, 1.0] {
                let s = Surface {
                    base_color: Vec3::new(0.9, 0.6, 0.3),
                    roughness,
                    metalness,
                    specular: 0.5,
                };
                for n_v in [0.2f32, 0.5, 0.9] {
                    let v = Vec3::new((1.0 - n_v * n_v).sqrt(), n_v, 0.0);
                    let integrated = directional_albedo(&s, v);
                    let fit = specular_albedo(&s, n_v);
                    let err = (fit - integrated).abs().max_element();
                    worst = worst.max(err);
                    assert!(
                        err < 0.01,
                        "r {roughness} m {metalness} n·v {n_v}: fit {fit}, integrated {integrated}"
                    );
                }
            }
        }
        eprintln!("worst absolute error of the table: {worst:.4}");
    }

    /// The GPU's reading of the table (bilinear over 32²) against
    /// integration, down to grazing views: within 0.015, 0.035 at 85°.
    #[test]
    fn the_tables_lookup_matches_integration() {
        let table = environment_table();
        for roughness in [0.05f32, 0.25, 0.45, 0.7, 0.95] {
            for n_v in [0.08f32, 0.3, 0.6, 0.97] {
                let s = Surface { base_color: Vec3::ONE, roughness, metalness: 1.0, specular: 0.5 };
                let v = Vec3::new((1.0 - n_v * n_v).sqrt(), n_v, 0.0);
                let integrated = directional_albedo(&s, v).x;
                let (a, b) = environment_lookup(&table, n_v, roughness);
                // At 85° the albedo falls steeply between texels.
                let tolerance = if n_v < 0.1 { 0.035 } else { 0.015 };
                assert!(
                    (a + b - integrated).abs() < tolerance,
                    "r {roughness} n·v {n_v}: {} vs {integrated}",
                    a + b
                );
            }
        }
        assert_eq!(
            environment_table_packed().len(),
            ENVIRONMENT_TABLE_SIZE * ENVIRONMENT_TABLE_SIZE / 2
        );
    }

    /// `specular = 0` is a Lambertian surface: nothing reflected, at any
    /// angle, and all of it diffuse.
    #[test]
    fn no_specular_is_lambertian() {
        let s =
            Surface { base_color: Vec3::splat(0.5), roughness: 0.3, metalness: 0.0, specular: 0.0 };
        for n_v in [0.05f32, 0.5, 1.0] {
            assert_eq!(specular_albedo(&s, n_v), Vec3::ZERO);
            assert_eq!(diffuse_weight(&s, n_v), Vec3::ONE);
        }
    }

    /// The closed form of a uniform sky of radiance L: irradiance πL on
    /// every upward normal, and the filtered sky L in every direction, so a
    /// surface sends back L times its directional albedo — all of L for a
    /// white dielectric (what the specular part takes the diffuse part
    /// loses: the white furnace), F0·L for a smooth metal at normal
    /// incidence, albedo·L for a Lambertian one.
    #[test]
    fn a_uniform_sky_is_reflected_as_its_closed_form() {
        let sky = Vec3::new(0.3, 0.5, 0.9);
        let r = Vec3::new(0.2, 0.9, -0.1).normalize();
        for level in [0, 2, SPECULAR_LEVELS - 1] {
            let p = prefiltered(|_| sky, r, level);
            assert!((p - sky).abs().max_element() < 1e-5, "level {level}: {p}");
        }
        let e = PI * sky;
        for n_v in [0.2f32, 0.6, 1.0] {
            for roughness in [0.1f32, 0.5, 0.9] {
                let white =
                    Surface { base_color: Vec3::ONE, roughness, metalness: 0.0, specular: 0.5 };
                let out = environment_radiance(&white, n_v, e, sky);
                assert!(
                    (out - sky).abs().max_element() < 1e-5,
                    "white furnace at n·v {n_v}, r {roughness}: {out}"
                );
            }
            let lambert = Surface {
                base_color: Vec3::splat(0.4),
                roughness: 0.5,
                metalness: 0.0,
                specular: 0.0,
            };
            let out = environment_radiance(&lambert, n_v, e, sky);
            assert!((out - 0.4 * sky).abs().max_element() < 1e-5);
        }
        let gold = Surface {
            base_color: Vec3::new(1.0, 0.78, 0.34),
            roughness: 0.0,
            metalness: 1.0,
            specular: 0.5,
        };
        let out = environment_radiance(&gold, 1.0, e, sky);
        assert!(
            (out - gold.base_color * sky).abs().max_element() < 0.02 * sky.max_element(),
            "{out}"
        );
    }

    /// Filtering a sky with one bright patch: the patch dims and its light
    /// reaches further as the roughness grows.
    #[test]
    fn filtering_widens_with_roughness() {
        let patch = |d: Vec3| if d.y > 0.95 { Vec3::ONE } else { Vec3::ZERO };
        let off = Vec3::new(0.5, 0.85, 0.0).normalize();
        let mut previous = 1.0 + 1e-6;
        for level in 1..SPECULAR_LEVELS {
            let at_patch = prefiltered(patch, Vec3::Y, level).x;
            assert!(at_patch < previous, "level {level}: {at_patch} after {previous}");
            previous = at_patch;
        }
        assert!(prefiltered(patch, off, 1).x < 0.05, "only GGX's tail");
        let beside = prefiltered(patch, off, SPECULAR_LEVELS - 1).x;
        assert!(beside > 0.05, "the roughest lobe reaches 32° off the patch: {beside}");
        assert_eq!(prefiltered(patch, Vec3::Y, 0), Vec3::ONE);
        assert_eq!(cube_level(level_roughness(3)), 3.0);
    }
}
