//! Ambient occlusion where objects meet the ground, the water's edge and
//! each other (issue #32 item 1). Each opaque primitive is an analytic
//! occluder — a sphere, or a box (a cylinder is the box of its height and
//! cross-section area) — and a point with normal n loses the share of the
//! sky's light the occluders cover: their cosine-weighted solid angle, the
//! form factor, in closed form. A sphere: cos θ·(r/d)² above the horizon and
//! Quílez's exact expression where it straddles it ("Sphere ambient
//! occlusion", 2014). A box: Lambert's formula for each face turned towards
//! the point, clipped to the point's horizon (the faces' projections tile
//! the box's silhouette). Several occluders leave the product of what each
//! leaves.
//!
//! Why analytic and not screen-space or baked: the scene's objects are
//! primitives, whose form factors are exact; the result does not depend on
//! what is on screen (no halos at edges, nothing lost in the reflections,
//! refractions and traced hits, which read the same occluders), costs no
//! extra pass or depth prepass, and follows moving bodies, which a bake
//! could not. Meshes from files and the terrain do not occlude (their
//! shapes are not primitives); the sun's shadow map covers the sun. WGSL
//! twin: `shaders/occlusion.wgsl`.

use glam::{Mat4, Vec3};
use std::f32::consts::PI;

/// At most this many occluders reach the GPU (the frame's uniform).
pub const MAX_OCCLUDERS: usize = 32;
/// The form factor an occluder is skipped below (its enclosing sphere's
/// bound, (R/d)²).
pub const NEGLIGIBLE: f32 = 0.002;
/// The occluder index of a surface that is none of them.
pub const NO_OCCLUDER: u32 = u32::MAX;

/// An occluder in world space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Occluder {
    Sphere {
        centre: Vec3,
        radius: f32,
    },
    /// A box: its centre and half-extents along its three (orthogonal) axes.
    Box {
        centre: Vec3,
        half_axes: [Vec3; 3],
    },
}

/// An occluder's shape in its object's space (the unit primitives: sphere
/// of radius ½, box [−½, ½]³, cylinder of radius ½ and height 1 along y).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    Sphere,
    Box,
    Cylinder,
}

/// Half-side of the square of a circle's area, per unit radius: √π / 2.
const CYLINDER_AS_BOX: f32 = 0.886_226_9;

impl Occluder {
    /// `shape` placed by `transform`. A scaled sphere is the sphere of the
    /// same volume.
    pub fn placed(shape: Shape, transform: &Mat4) -> Occluder {
        let centre = transform.transform_point3(Vec3::ZERO);
        let axis = |v: Vec3| transform.transform_vector3(v * 0.5);
        let [x, y, z] = [axis(Vec3::X), axis(Vec3::Y), axis(Vec3::Z)];
        match shape {
            Shape::Sphere => {
                let radius = (x.length() * y.length() * z.length()).cbrt();
                Occluder::Sphere { centre, radius }
            }
            Shape::Box => Occluder::Box { centre, half_axes: [x, y, z] },
            Shape::Cylinder => {
                Occluder::Box { centre, half_axes: [x * CYLINDER_AS_BOX, y, z * CYLINDER_AS_BOX] }
            }
        }
    }

    /// The share of the cosine-weighted hemisphere above normal n at p it
    /// covers (0 to 1).
    pub fn form_factor(&self, p: Vec3, n: Vec3) -> f32 {
        match *self {
            Occluder::Sphere { centre, radius } => sphere_form_factor(centre - p, radius, n),
            Occluder::Box { centre, half_axes } => box_form_factor(centre, half_axes, p, n),
        }
    }

    /// Whether it can hide as much as [`NEGLIGIBLE`] of the sky above n
    /// at p, by its enclosing sphere: not when that is too small or far, or
    /// wholly below the horizon (the GPU skips it then too).
    pub fn may_occlude(&self, p: Vec3, n: Vec3) -> bool {
        let (centre, reach) = match *self {
            Occluder::Sphere { centre, radius } => (centre, radius),
            Occluder::Box { centre, half_axes: [x, y, z] } => (centre, (x + y + z).length()),
        };
        let to_centre = centre - p;
        reach * reach >= NEGLIGIBLE * to_centre.length_squared() && n.dot(to_centre) >= -reach
    }

    /// As the GPU holds it (`Occluder` in shaders/frame.wgsl): the centre
    /// and the shape (0 sphere, 1 box), then the half-axes (a sphere's
    /// radius in the first one's w).
    pub fn packed(&self) -> [[f32; 4]; 4] {
        match *self {
            Occluder::Sphere { centre, radius } => {
                [centre.extend(0.0).into(), [0.0, 0.0, 0.0, radius], [0.0; 4], [0.0; 4]]
            }
            Occluder::Box { centre, half_axes: [x, y, z] } => [
                centre.extend(1.0).into(),
                x.extend(0.0).into(),
                y.extend(0.0).into(),
                z.extend(0.0).into(),
            ],
        }
    }
}

/// The form factor of a sphere of radius r whose centre is at `to_centre`
/// from the point, for normal n: exact above and below the horizon and
/// where the sphere straddles it; 1 inside it.
pub fn sphere_form_factor(to_centre: Vec3, r: f32, n: Vec3) -> f32 {
    let d = to_centre.length();
    if d <= r {
        return 1.0;
    }
    let nl = n.dot(to_centre / d);
    let h = d / r;
    let h2 = h * h;
    let k2 = 1.0 - h2 * nl * nl;
    if k2 <= 0.0 {
        // Wholly above (or below) the horizon.
        return nl.max(0.0) / h2;
    }
    let res = nl * (-nl * ((h2 - 1.0) / (1.0 - nl * nl)).sqrt()).clamp(-1.0, 1.0).acos()
        - (k2 * (h2 - 1.0)).sqrt();
    ((res / h2 + (k2 / (h2 - 1.0)).sqrt().atan()) / PI).clamp(0.0, 1.0)
}

/// Lambert's formula for a polygon's form factor seen from p with normal n,
/// after clipping it to the hemisphere above n.
pub fn polygon_form_factor(corners: &[Vec3], p: Vec3, n: Vec3) -> f32 {
    // Sutherland–Hodgman against the plane n·(x − p) = 0.
    let mut clipped: Vec<Vec3> = Vec::with_capacity(corners.len() + 1);
    for (i, &a) in corners.iter().enumerate() {
        let b = corners[(i + 1) % corners.len()];
        let (da, db) = (n.dot(a - p), n.dot(b - p));
        if da >= 0.0 {
            clipped.push(a);
        }
        if (da >= 0.0) != (db >= 0.0) {
            clipped.push(a + (b - a) * (da / (da - db)));
        }
    }
    if clipped.len() < 3 {
        return 0.0;
    }
    let mut sum = 0.0;
    for (i, &a) in clipped.iter().enumerate() {
        let b = clipped[(i + 1) % clipped.len()];
        let (u, v) = ((a - p).normalize_or_zero(), (b - p).normalize_or_zero());
        let c = u.cross(v);
        let len = c.length();
        if len > 1e-9 {
            sum += u.dot(v).clamp(-1.0, 1.0).acos() * n.dot(c / len);
        }
    }
    (sum / (2.0 * PI)).abs()
}

/// The form factor of a box: its faces turned towards p, each clipped.
pub fn box_form_factor(centre: Vec3, half_axes: [Vec3; 3], p: Vec3, n: Vec3) -> f32 {
    let mut total = 0.0;
    for axis in 0..3 {
        let (a, b, c) = (half_axes[axis], half_axes[(axis + 1) % 3], half_axes[(axis + 2) % 3]);
        for side in [-1.0f32, 1.0] {
            let face = centre + a * side;
            // Turned towards p, which is not on its plane (a point on a
            // face would see that face as its whole sky).
            if a.normalize().dot(p - face) * side <= 1e-3 {
                continue;
            }
            let corners = [face - b - c, face + b - c, face + b + c, face - b + c];
            total += polygon_form_factor(&corners, p, n);
        }
    }
    total.min(1.0)
}

/// What the occluders but the surface's own (`own`, an index, or
/// [`NO_OCCLUDER`]) leave of the sky's light at p (normal n): the product
/// of each one's 1 − F.
pub fn sky_visibility(occluders: &[Occluder], p: Vec3, n: Vec3, own: u32) -> f32 {
    occluders
        .iter()
        .enumerate()
        .filter(|(i, o)| *i as u32 != own && o.may_occlude(p, n))
        .map(|(_, o)| 1.0 - o.form_factor(p, n))
        .product()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The occluder's cosine-weighted share of the hemisphere by Monte
    /// Carlo: cosine-distributed rays (stratified), the fraction that hit.
    fn monte_carlo(hit: impl Fn(Vec3) -> bool, n: Vec3) -> f32 {
        let t = if n.y.abs() < 0.9 { Vec3::Y.cross(n).normalize() } else { Vec3::X };
        let b = n.cross(t);
        let k = 400;
        let mut hits = 0;
        for i in 0..k {
            for j in 0..k {
                let (u, v) = ((i as f32 + 0.5) / k as f32, (j as f32 + 0.5) / k as f32);
                let (r, phi) = (u.sqrt(), 2.0 * PI * v);
                let d = t * (r * phi.cos()) + b * (r * phi.sin()) + n * (1.0 - u).max(0.0).sqrt();
                hits += hit(d) as u32;
            }
        }
        hits as f32 / (k * k) as f32
    }

    fn ray_hits_sphere(p: Vec3, d: Vec3, c: Vec3, r: f32) -> bool {
        let oc = p - c;
        let b = oc.dot(d);
        let disc = b * b - (oc.length_squared() - r * r);
        disc >= 0.0 && -b + disc.sqrt() > 0.0
    }

    fn ray_hits_box(p: Vec3, d: Vec3, c: Vec3, h: [Vec3; 3]) -> bool {
        let (mut t0, mut t1) = (0.0f32, f32::INFINITY);
        for a in h {
            let len = a.length();
            let axis = a / len;
            let (o, dd) = (axis.dot(p - c), axis.dot(d));
            if dd.abs() < 1e-9 {
                if o.abs() > len {
                    return false;
                }
                continue;
            }
            let (ta, tb) = ((-len - o) / dd, (len - o) / dd);
            t0 = t0.max(ta.min(tb));
            t1 = t1.min(ta.max(tb));
        }
        t0 <= t1
    }

    /// Spheres above, straddling and below the horizon, near and far,
    /// against cosine-weighted ray casting (within 0.005 of the hemisphere).
    #[test]
    fn the_sphere_form_factor_is_exact_at_every_elevation() {
        let n = Vec3::Y;
        for (dist, elevation_deg) in [
            (2.0f32, 90.0f32),
            (2.0, 40.0),
            (2.0, 10.0),
            (1.3, 0.0),
            (3.0, -15.0),
            (1.05, 20.0),
            (4.0, -40.0),
        ] {
            let e = elevation_deg.to_radians();
            let c = Vec3::new(e.cos(), e.sin(), 0.3 * e.cos()).normalize() * dist;
            let exact = sphere_form_factor(c, 1.0, n);
            let mc = monte_carlo(|d| ray_hits_sphere(Vec3::ZERO, d, c, 1.0), n);
            assert!(
                (exact - mc).abs() < 0.005,
                "d {dist}, elevation {elevation_deg}°: closed form {exact}, rays {mc}"
            );
        }
        // Resting on the ground, a sphere covers the whole sky at the contact point.
        assert!((sphere_form_factor(Vec3::Y, 1.0, Vec3::Y) - 1.0).abs() < 1e-5);
    }

    /// Boxes — beside the point (walls rising from its ground), overhead,
    /// tilted and straddling the horizon, a cylinder's box — against ray
    /// casting.
    #[test]
    fn the_box_form_factor_matches_ray_casting() {
        let tilt = Mat4::from_rotation_y(0.5) * Mat4::from_rotation_x(0.3);
        let cases: [(Vec3, [Vec3; 3], Vec3, Vec3); 5] = [
            // A 2 m cube standing on the ground, the point 0.3 m from its side.
            (Vec3::new(1.3, 1.0, 0.0), [Vec3::X, Vec3::Y, Vec3::Z], Vec3::ZERO, Vec3::Y),
            // A slab overhead.
            (
                Vec3::new(0.0, 1.5, 0.0),
                [Vec3::X * 2.0, Vec3::Y * 0.2, Vec3::Z],
                Vec3::ZERO,
                Vec3::Y,
            ),
            // A tilted box half below the horizon.
            (
                Vec3::new(1.5, 0.2, 0.5),
                [
                    tilt.transform_vector3(Vec3::X * 0.8),
                    tilt.transform_vector3(Vec3::Y * 0.6),
                    tilt.transform_vector3(Vec3::Z * 0.5),
                ],
                Vec3::ZERO,
                Vec3::Y,
            ),
            // A wall seen by a vertical face beside it.
            (
                Vec3::new(0.0, 1.0, -1.0),
                [Vec3::X * 3.0, Vec3::Y, Vec3::Z * 0.2],
                Vec3::new(0.0, 1.0, 0.5),
                -Vec3::Z,
            ),
            // A point on the box's own face sees none of it.
            (Vec3::ZERO, [Vec3::X, Vec3::Y, Vec3::Z], Vec3::new(0.0, 1.0, 0.0), Vec3::Y),
        ];
        for (c, h, p, n) in cases {
            let exact = box_form_factor(c, h, p, n);
            let mc = monte_carlo(|d| ray_hits_box(p + d * 1e-4, d, c, h), n);
            assert!(
                (exact - mc).abs() < 0.006,
                "box at {c}, point {p} n {n}: closed form {exact}, rays {mc}"
            );
        }
    }

    /// Placing the unit primitives: a sphere keeps its volume, a cylinder
    /// its cross-section area, and the packed form says which is which.
    #[test]
    fn primitives_place_as_occluders() {
        let t = Mat4::from_scale_rotation_translation(
            Vec3::new(2.0, 2.0, 2.0),
            glam::Quat::IDENTITY,
            Vec3::Y,
        );
        assert_eq!(
            Occluder::placed(Shape::Sphere, &t),
            Occluder::Sphere { centre: Vec3::Y, radius: 1.0 }
        );
        let Occluder::Box { half_axes, .. } = Occluder::placed(Shape::Cylinder, &t) else {
            panic!("a box")
        };
        let side = 2.0 * half_axes[0].length();
        assert!((side * side - PI * 1.0).abs() < 1e-4, "{side}");
        assert_eq!(Occluder::placed(Shape::Box, &t).packed()[0][3], 1.0);
        let far = [Occluder::Sphere { centre: Vec3::new(0.0, 1.0, 100.0), radius: 0.5 }];
        assert!(sky_visibility(&far, Vec3::ZERO, Vec3::Y, NO_OCCLUDER) > 0.9999);
        assert_eq!(sky_visibility(&far, Vec3::new(0.0, 1.0, 99.5), Vec3::Y, 0), 1.0);
    }
}
