//! The frame plan: every decision about one frame, made once, on the CPU,
//! from the scene, the camera, the time and what the renderer holds (the
//! geometry's bounds, the surface's reach, what is still current). The
//! renderer then uploads what the plan says and records the passes it lists;
//! nothing is decided twice. Pure CPU code, unit-tested without a GPU.

use crate::formats::{REFRACTION_MARGIN, STENCIL_AIR, STENCIL_WATER};
use crate::uniforms::{
    FrameCaustics, FrameFog, FrameLight, FrameModes, FrameObjects, FrameOcclusion, FrameProjective,
    FrameShadow, FrameSurface, FrameUniforms, FrameView, FrameVolume, FrameWater,
};
use glam::{Mat4, Vec3};
use hydrolux_core::camera::Camera;
use hydrolux_core::caustics::flat_floor_irradiance;
use hydrolux_core::godrays::{TubeRegion, deepest_needed};
use hydrolux_core::medium::UnderwaterLight;
use hydrolux_core::projective::{mirror_matrix, shadow_space, sun_view_projection};
use hydrolux_core::scene::{DebugView, GodRayMethod, Scene, WaterModel};
use hydrolux_core::sky::SkyParams;
use hydrolux_core::tonemap::exposure_scale;
use hydrolux_core::waves::ocean::REPEAT_PERIOD_S;

/// What the renderer holds that a frame's decisions depend on, besides the
/// scene and the camera.
#[derive(Clone, Copy, Debug)]
pub(crate) struct World {
    /// Bounds of the shadow casters (`None`: nothing casts shadows).
    pub shadow_bounds: Option<(Vec3, Vec3)>,
    /// Bounds of the refractive objects (`None`: there are none).
    pub refractive_bounds: Option<(Vec3, Vec3)>,
    /// The scene has opaque geometry (objects, floor, terrain).
    pub has_geometry: bool,
    /// How far (m) the surface rises or falls from y = 0 in practice.
    pub vertical_reach: f32,
    /// How far (m) the surface's displacement reaches sideways and up, for
    /// culling its tiles.
    pub cull_margin: f32,
    /// The surface changes by itself from frame to frame (waves), so what
    /// is computed from it (caustics) is due every frame.
    pub surface_moving: bool,
    /// Sub-pixel slope variance the surface does not resolve, per axis.
    pub unresolved_variance: [f32; 2],
    /// Shadow map and object light-view sizes (texels per side).
    pub shadow_resolution: u32,
    pub object_light_resolution: u32,
    /// The sky's parameters and its irradiance on a horizontal plane.
    pub sky: SkyParams,
    pub sky_irradiance: Vec3,
    /// The sky's and the grey world's light on every normal.
    pub sky_light: hydrolux_core::irradiance::IrradianceSh,
    /// The caustic map, and the objects' light paths, still match the scene.
    pub caustics_current: bool,
    pub object_light_current: bool,
    /// The ambient occluders where they are now (`hydrolux_core::occlusion`).
    pub occlusion: FrameOcclusion,
    /// The main view's sub-pixel offset this frame (pixels, x right, y
    /// down; the anti-aliasing's jitter, zero when it is off).
    pub jitter_px: glam::Vec2,
}

/// Floor caustics this frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct CausticsPlan {
    /// The patch the maps tile (m) and the floor depth they reach (m).
    pub patch: [f32; 2],
    pub depth: f32,
    /// The maps must be (re)computed this frame: the waves move, or the
    /// scene changed since they were made.
    pub due: bool,
}

/// God rays this frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct GodRaysPlan {
    /// Photons per side of the surface's tube region (0 in the air: the
    /// fog is marched) and march steps per texel.
    pub photons: u32,
    pub steps: u32,
    /// The god-ray buffer's size (texels).
    pub buffer: (u32, u32),
    /// The tube region's centre (x, z) and half side (m); zero in the air.
    pub region_centre: [f32; 2],
    pub region_half: f32,
    /// Half-width (m) of a ribbon: the surface photons' spacing, or in the
    /// air the objects' light-view texel (their paths' width).
    pub ribbon_half_width: f32,
    /// How far from the eye shafts are drawn (m), and the depth the
    /// surface's tubes end at (m; 0 in the air).
    pub distance: f32,
    pub end_depth: f32,
    /// The medium the shafts are in (its stencil value) and its scattering
    /// and extinction (1/m) with the phase function's g.
    pub stencil: u32,
    pub scattering: [f32; 3],
    pub phase_g: f32,
    pub extinction: [f32; 3],
    /// For a viewer in the air (the fog and refractive objects' paths)
    /// rather than in the water (the surface's photons).
    pub in_air: bool,
}

/// Refractive objects' light this frame.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ObjectLightPlan {
    /// Their light view (world → clip).
    pub view_proj: Mat4,
    /// Texels per side of the light view.
    pub resolution: u32,
    /// Area (m²) of one light-view texel: the light one path carries.
    pub texel_area: f32,
    /// Height (m) of the floor the paths land on, and whether there is one.
    pub floor_y: f32,
    pub floor: bool,
    /// Farthest (m) a path may travel: the light view's diameter.
    pub reach: f32,
    /// The light paths and caustic map must be (re)made this frame.
    pub due: bool,
}

/// The offscreen views a frame draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Offscreen {
    /// Reflection and refraction for a viewer in the air.
    pub air: bool,
    /// Reflection under and refraction over for a viewer in the water.
    pub water: bool,
}

/// Every matrix a frame draws with.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Matrices {
    /// The main view as drawn: the camera's, shifted by the jitter.
    pub view_proj: Mat4,
    /// The camera's own, without the jitter (what reprojection uses).
    pub unjittered: Mat4,
    pub reflection: Mat4,
    pub refraction: Mat4,
    /// The sun's shadow view (`None`: nothing casts shadows, or the sun is down).
    pub shadow: Option<Mat4>,
}

/// One frame, decided.
#[derive(Clone, Debug)]
pub(crate) struct FramePlan {
    pub camera: Camera,
    pub size: (u32, u32),
    pub time: f64,
    pub has_water: bool,
    /// The FFT ocean is simulated this frame.
    pub ocean: bool,
    pub matrices: Matrices,
    pub offscreen: Offscreen,
    pub caustics: Option<CausticsPlan>,
    pub godrays: Option<GodRaysPlan>,
    pub object_light: Option<ObjectLightPlan>,
    /// How far (m) along refracted paths the water shader marches god rays
    /// for a viewer above the water (0: none).
    pub shafts_from_above: f32,
    /// The surface's culling margin (m).
    pub cull_margin: f32,
    /// The error view's reference drawing of the liquid's surface
    /// (`error_view::is_surface_reference`).
    pub liquid_reference: bool,
    /// What stateful simulations do to reach this frame's time (set by the
    /// renderer from its simulation clock).
    pub simulation: hydrolux_core::clock::Advance,
    /// The frame globals, filled from the decisions above.
    pub frame: FrameUniforms,
}

impl FramePlan {
    pub fn new(scene: &Scene, world: &World, camera: Camera, size: (u32, u32), time: f64) -> Self {
        let s = scene;
        let has_water = s.has_water();
        let aspect = size.0.max(1) as f32 / size.1.max(1) as f32;
        let sun = s.sun_direction();
        let sun_up = sun.y > 0.0;
        let travel = UnderwaterLight::new(sun, Vec3::ONE, Vec3::ZERO, s.water.ior).sun_travel;
        let unjittered = camera.view_projection(aspect);
        let jitter = hydrolux_core::antialias::jitter_matrix(world.jitter_px, size);
        let matrices = Matrices {
            view_proj: jitter * unjittered,
            unjittered,
            reflection: camera.view_projection_widened(aspect, s.render.fov_margin)
                * mirror_matrix(),
            refraction: camera.view_projection_widened(aspect, REFRACTION_MARGIN),
            shadow: world.shadow_bounds.filter(|_| sun_up).map(|b| shadow_fit(b, sun, travel)),
        };
        // A camera in the air needs the first pair, one in the water the
        // second; one within wave reach of the surface may see both media.
        let reach = world.vertical_reach;
        let y = camera.position.y;
        // Ray-traced water looks nothing up in them (the debug views still
        // show them).
        let traced = s.water.method == hydrolux_core::scene::WaterMethod::Raytrace
            && matches!(s.render.view, DebugView::Final | DebugView::Error);
        let offscreen = Offscreen {
            air: has_water && y > -reach && !traced,
            water: has_water && y < reach && !traced,
        };
        let caustics = s.has_caustics().then(|| CausticsPlan {
            patch: s.surface_patch(),
            depth: s.floor.depth,
            due: world.surface_moving || !world.caustics_current,
        });
        let object_light = object_light(s, world, sun);
        let godrays = godrays(s, world, &camera, size, sun, travel, object_light.as_ref());
        let above = y > -reach;
        let shafts_from_above =
            if s.godrays.method == GodRayMethod::Off || !above || caustics.is_none() {
                0.0
            } else {
                s.godrays.distance
            };
        let mut plan = FramePlan {
            camera,
            size,
            time,
            has_water,
            ocean: s.water.model == WaterModel::Fft,
            matrices,
            offscreen,
            caustics,
            godrays,
            object_light,
            shafts_from_above,
            cull_margin: world.cull_margin,
            liquid_reference: crate::error_view::is_surface_reference(s),
            simulation: hydrolux_core::clock::Advance { reset: false, from: 0, steps: 0 },
            frame: FrameUniforms::default(),
        };
        plan.frame = plan.frame_uniforms(s, world);
        plan
    }

    fn frame_uniforms(&self, s: &Scene, world: &World) -> FrameUniforms {
        let camera = &self.camera;
        let m = &self.matrices;
        let sky = &world.sky;
        let exposure = exposure_scale(s.render.exposure);
        let sun = Vec3::from_slice(&sky.sun_illuminance[..3]) * exposure;
        let ambient = world.sky_irradiance * exposure;
        let sun_dir = Vec3::from_slice(&sky.sun_direction[..3]);
        let under = UnderwaterLight::new(sun_dir, sun, ambient, s.water.ior)
            .with_floor(s.floor.depth, s.floor.material.mean_albedo());
        let medium = s.medium();
        let size = self.size;
        FrameUniforms {
            view: FrameView {
                view_proj: m.view_proj.to_cols_array_2d(),
                inv_view_proj: m.view_proj.inverse().to_cols_array_2d(),
                position: camera.position.into(),
                time: self.time.rem_euclid(REPEAT_PERIOD_S) as f32,
                size: [size.0 as f32, size.1 as f32],
                inv_size: [1.0 / size.0.max(1) as f32, 1.0 / size.1.max(1) as f32],
            },
            light: FrameLight {
                sun_dir: sun_dir.into(),
                cos_sun_radius: sky.sun_direction[3],
                sun_illuminance: sun.into(),
                inv_sun_solid_angle: sky.sun_illuminance[3],
                sky_ambient: ambient.into(),
                exposure,
                sun_travel: under.sun_travel.into(),
                sun_travel_cos: -under.sun_travel.y,
                sun_underwater: under.sun_irradiance.into(),
                floor_depth: under.floor_depth,
                sky_underwater: under.sky_irradiance.into(),
                floor_albedo: under.floor_albedo,
                sky_light: world.sky_light.coefficients.map(|c| (c * exposure).extend(0.0).into()),
            },
            water: FrameWater {
                body_color: s.water.body_color,
                ior: s.water.ior,
                absorption: medium.absorption.into(),
                phase_g: s.water.phase_g,
                scattering: medium.scattering.into(),
                fresnel_power: s.water.fresnel_power,
                reflection_height: s.water.reflection_height,
                refraction_depth: s.water.refraction_depth,
                refraction_max: s.water.refraction_max,
                simple_attenuation: s.water.simple_attenuation,
                has_water: self.has_water as u32,
                ..Default::default()
            },
            surface: FrameSurface {
                unresolved_variance: world.unresolved_variance,
                base_spacing: crate::surface_kind::BASE_SPACING,
                rings: crate::surface_kind::DISPLACED_RINGS as f32,
            },
            projective: FrameProjective {
                reflection_view_proj: m.reflection.to_cols_array_2d(),
                refraction_view_proj: m.refraction.to_cols_array_2d(),
                inv_refraction_view_proj: m.refraction.inverse().to_cols_array_2d(),
                reflection_texels_per_radian: reflection_texels_per_radian(s, camera, size),
                has_geometry: world.has_geometry as u32,
                ..Default::default()
            },
            shadow: FrameShadow {
                view_proj: m.shadow.unwrap_or(Mat4::IDENTITY).to_cols_array_2d(),
                enabled: m.shadow.is_some() as u32,
                size: world.shadow_resolution,
                ..Default::default()
            },
            caustics: match self.caustics {
                Some(c) => FrameCaustics {
                    patch_size: c.patch,
                    floor_depth: c.depth,
                    inv_flat_value: 1.0 / flat_floor_irradiance(sun_dir, s.water.ior).max(1e-4),
                    layers: s.caustics.layers,
                    ..Default::default()
                },
                None => FrameCaustics::default(),
            },
            volume: FrameVolume {
                godray_distance: self.godrays.filter(|g| !g.in_air).map_or(0.0, |g| g.distance),
                fog_marched: self.godrays.is_some_and(|g| g.in_air) as u32,
                shafts_from_above: self.shafts_from_above,
                _pad0: 0.0,
            },
            fog: FrameFog {
                scattering: s.air.fog,
                g: s.air.fog_g,
                distance: s.air.fog_distance,
                sky_fraction: s.air.fog_sky,
                // Either sky model's air: the atmosphere its turbidity gives.
                air_extinction: (hydrolux_core::atmosphere::Atmosphere::earth(s.sky.turbidity)
                    .extinction(0.0)
                    / 1000.0)
                    .into(),
                _pad0: 0.0,
            },
            occlusion: world.occlusion,
            objects: FrameObjects {
                light_view_proj: self
                    .object_light
                    .map_or(Mat4::IDENTITY, |o| o.view_proj)
                    .to_cols_array_2d(),
                enabled: self.object_light.is_some() as u32,
                // Receivers within ~1% of the light box's depth of where the light landed.
                depth_tolerance: 0.01,
                ..Default::default()
            },
            modes: FrameModes {
                fresnel: crate::modes::fresnel(s.water.fresnel),
                tonemap: crate::modes::tonemap(s.render.tonemap),
                debug_view: crate::modes::debug_view(s.render.view),
                optics: crate::modes::optics(s.water.optics),
                refraction_lookup: crate::modes::refraction(s.water.refraction),
                ..Default::default()
            },
        }
    }
}

/// The sun's orthographic view-projection around the shadow casters'
/// bounds, in refraction-bent shadow space.
fn shadow_fit(bounds: (Vec3, Vec3), sun: Vec3, travel: Vec3) -> Mat4 {
    let mut bent = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
    for c in hydrolux_core::geometry::Mesh::box_corners(bounds) {
        let p = shadow_space(c, sun, travel);
        bent = (bent.0.min(p), bent.1.max(p));
    }
    sun_view_projection(sun, bent.0, bent.1)
}

/// Texels of the reflection texture per radian of view angle (at its
/// centre): how many texels a reflected ray spread of 2σ covers.
fn reflection_texels_per_radian(s: &Scene, camera: &Camera, size: (u32, u32)) -> f32 {
    let r = &s.render;
    let height = (size.1 as f32 * r.reflection_resolution * (1.0 + r.fov_margin)).round().max(1.0);
    let half_tan = (0.5 * camera.fov_y_deg.to_radians()).tan() * (1.0 + r.fov_margin);
    0.5 * height / half_tan
}

/// The refractive objects' light view and the paths' parameters, when there
/// are such objects and the sun is up: an orthographic view along the sun
/// around them and the floor below, wide enough for light they bend sideways.
fn object_light(s: &Scene, world: &World, sun: Vec3) -> Option<ObjectLightPlan> {
    let (lo, hi) = world.refractive_bounds?;
    if sun.y <= 0.0 {
        return None;
    }
    let floor = s.floor.depth > 0.0;
    let floor_y = if floor { -s.floor.depth } else { lo.y - (hi.y - lo.y) };
    let reach = (hi.y - floor_y).max(0.0);
    let lo = Vec3::new(lo.x - reach, floor_y.min(lo.y), lo.z - reach);
    let hi = Vec3::new(hi.x + reach, hi.y, hi.z + reach);
    let view_proj = sun_view_projection(sun, lo, hi);
    let radius = (0.5 * (hi - lo)).length();
    let k = world.object_light_resolution;
    let texel = 2.0 * radius / k as f32;
    Some(ObjectLightPlan {
        view_proj,
        resolution: k,
        texel_area: texel * texel,
        floor_y,
        floor,
        reach: 4.0 * radius,
        due: !world.object_light_current,
    })
}

/// The god rays' parameters when they are drawn this frame: for a viewer in
/// (or within wave reach of) the water, the surface's photons; for one in
/// fog, the sun marched through the shadow map and the objects' paths.
fn godrays(
    s: &Scene,
    world: &World,
    camera: &Camera,
    size: (u32, u32),
    sun: Vec3,
    travel: Vec3,
    object_light: Option<&ObjectLightPlan>,
) -> Option<GodRaysPlan> {
    let g = &s.godrays;
    if g.method == GodRayMethod::Off || sun.y <= 0.0 {
        return None;
    }
    let scaled = |n: u32| ((n as f32 * g.resolution).round() as u32).max(1);
    let buffer = (scaled(size.0), scaled(size.1));
    if s.has_water() && camera.position.y < world.vertical_reach {
        let medium = s.medium();
        let region = TubeRegion::around(camera.position, travel, g.distance);
        let deepest = deepest_needed(camera.position, g.distance);
        let end_depth = if s.floor.depth > 0.0 { s.floor.depth.min(deepest) } else { deepest };
        return Some(GodRaysPlan {
            photons: g.photons,
            steps: g.steps,
            buffer,
            region_centre: [region.centre.x, region.centre.y],
            region_half: region.half,
            ribbon_half_width: region.spacing(g.photons),
            distance: g.distance,
            end_depth,
            stencil: STENCIL_WATER,
            scattering: medium.scattering.into(),
            phase_g: s.water.phase_g,
            extinction: medium.extinction().into(),
            in_air: false,
        });
    }
    if s.air.fog <= 0.0 {
        return None;
    }
    let half_width = object_light.map_or(0.0, |o| o.texel_area.sqrt());
    let fog = s.air.fog;
    Some(GodRaysPlan {
        photons: 0,
        steps: g.steps,
        buffer,
        region_centre: [0.0, 0.0],
        region_half: 0.0,
        ribbon_half_width: half_width,
        distance: s.air.fog_distance,
        end_depth: 0.0,
        stencil: STENCIL_AIR,
        scattering: [fog; 3],
        phase_g: s.air.fog_g,
        extinction: [fog; 3],
        in_air: true,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use hydrolux_core::sky::sky_irradiance_up;

    fn world(scene: &Scene) -> World {
        let sky = scene.sky_params();
        World {
            shadow_bounds: Some((Vec3::new(-5.0, -4.0, -5.0), Vec3::new(5.0, 1.0, 5.0))),
            refractive_bounds: None,
            has_geometry: true,
            vertical_reach: 0.5,
            cull_margin: 2.0,
            surface_moving: matches!(scene.water.model, WaterModel::Fft | WaterModel::Sines),
            unresolved_variance: [1e-3, 1e-3],
            shadow_resolution: 1024,
            object_light_resolution: 1,
            occlusion: FrameOcclusion::default(),
            sky,
            sky_irradiance: sky_irradiance_up(&hydrolux_core::sky::Sky::new(sky)),
            sky_light: hydrolux_core::irradiance::sky_light(&hydrolux_core::sky::Sky::new(sky)),
            caustics_current: false,
            object_light_current: false,
            jitter_px: glam::Vec2::ZERO,
        }
    }

    fn plan(scene: &Scene, world: &World, y: f32) -> FramePlan {
        let mut camera = scene.camera();
        camera.position.y = y;
        FramePlan::new(scene, world, camera, (320, 180), 1.5)
    }

    #[test]
    fn a_viewer_in_the_air_or_water_gets_its_views_and_god_rays() {
        let s = Scene::load("pool", &[]).unwrap();
        let w = world(&s);
        let air = plan(&s, &w, 5.0);
        assert_eq!(air.offscreen, Offscreen { air: true, water: false });
        // God rays in the water only; from above, shafts are marched along
        // refracted paths through the caustic layers instead.
        assert!(air.godrays.is_none());
        assert_eq!(air.shafts_from_above, s.godrays.distance);
        let under = plan(&s, &w, -1.0);
        assert_eq!(under.offscreen, Offscreen { air: false, water: true });
        let g = under.godrays.expect("god rays under water");
        assert!(!g.in_air);
        assert_eq!(under.frame.volume.godray_distance, s.godrays.distance);
        assert_eq!(under.shafts_from_above, 0.0);
        // Within wave reach both media may show: both pairs are drawn.
        let near = plan(&s, &w, 0.2);
        assert_eq!(near.offscreen, Offscreen { air: true, water: true });
    }

    #[test]
    fn caustics_are_due_while_the_waves_move_or_the_scene_changed() {
        let moving = Scene::load("underwater", &[]).unwrap();
        let mut w = world(&moving);
        w.caustics_current = true;
        let c = plan(&moving, &w, -2.0).caustics.expect("caustics on");
        assert!(c.due, "FFT waves move: recompute every frame");
        assert_eq!(c.depth, moving.floor.depth);
        let still = Scene::load("underwater", &["water.model=\"flat\"".into()]).unwrap();
        let mut w = World { surface_moving: false, ..w };
        assert!(!plan(&still, &w, -2.0).caustics.unwrap().due, "a still surface keeps its map");
        w.caustics_current = false;
        assert!(plan(&still, &w, -2.0).caustics.unwrap().due);
        let off = Scene::load("underwater", &["caustics.method=\"off\"".into()]).unwrap();
        let p = plan(&off, &w, -2.0);
        assert!(p.caustics.is_none());
        assert_eq!(p.frame.caustics.patch_size, [0.0, 0.0]);
        assert_eq!(p.shafts_from_above, 0.0, "no caustic layers to march through");
    }

    #[test]
    fn no_sun_no_shadows_caustics_or_god_rays() {
        let s = Scene::load("underwater", &["sun.elevation_deg=-5".into()]).unwrap();
        let p = plan(&s, &world(&s), -2.0);
        assert!(p.matrices.shadow.is_none() && p.caustics.is_none() && p.godrays.is_none());
        assert_eq!(p.frame.shadow.enabled, 0);
    }

    #[test]
    fn frame_globals_carry_the_scene_and_the_camera() {
        let s = Scene::load("harbor", &["water.fresnel=\"schlick\"".into()]).unwrap();
        let w = world(&s);
        let p = plan(&s, &w, 3.0);
        let f = &p.frame;
        assert_eq!(f.view.position, [p.camera.position.x, 3.0, p.camera.position.z]);
        assert_eq!(f.view.time, 1.5);
        assert_eq!(f.view.size, [320.0, 180.0]);
        assert_eq!(f.modes.fresnel, 1);
        assert_eq!(f.water.ior, s.water.ior);
        assert_eq!(f.water.absorption, <[f32; 3]>::from(s.medium().absorption));
        assert_eq!(f.water.has_water, 1);
        assert_eq!(f.shadow.enabled, 1);
        assert_eq!(f.shadow.size, 1024);
        assert_eq!(f.projective.has_geometry, 1);
        // The inverse really inverts.
        let vp = Mat4::from_cols_array_2d(&f.view.view_proj);
        let inv = Mat4::from_cols_array_2d(&f.view.inv_view_proj);
        assert!((vp * inv).abs_diff_eq(Mat4::IDENTITY, 1e-4));
        // Time is reduced modulo the ocean's repeat period, exactly as the
        // phases are.
        let late = FramePlan::new(&s, &w, p.camera, (320, 180), REPEAT_PERIOD_S + 2.0);
        assert!((late.frame.view.time - 2.0).abs() < 1e-3);
    }

    #[test]
    fn the_shadow_fit_contains_every_caster_corner() {
        let s = Scene::load("pool", &[]).unwrap();
        let w = world(&s);
        let m = plan(&s, &w, 5.0).matrices.shadow.expect("shadows");
        let sun = s.sun_direction();
        let travel = UnderwaterLight::new(sun, Vec3::ONE, Vec3::ZERO, s.water.ior).sun_travel;
        for c in hydrolux_core::geometry::Mesh::box_corners(w.shadow_bounds.unwrap()) {
            let clip = m.project_point3(shadow_space(c, sun, travel));
            assert!(clip.x.abs() <= 1.0 + 1e-4 && clip.y.abs() <= 1.0 + 1e-4, "{clip}");
            assert!((-1e-4..=1.0 + 1e-4).contains(&clip.z), "{clip}");
        }
    }

    #[test]
    fn a_room_without_water_draws_no_water_views_and_fog_is_marched() {
        let s = Scene::load("water_dragon", &[]).unwrap();
        let mut w = world(&s);
        w.refractive_bounds = Some((Vec3::new(-1.0, 0.0, -1.0), Vec3::new(1.0, 2.0, 1.0)));
        w.object_light_resolution = 256;
        let p = plan(&s, &w, 1.0);
        assert!(!p.has_water);
        assert_eq!(p.offscreen, Offscreen { air: false, water: false });
        let o = p.object_light.expect("refractive objects are lit");
        assert!(o.due);
        assert_eq!(p.frame.objects.enabled, 1);
        let g = p.godrays.expect("fog is lit");
        assert!(g.in_air);
        assert_eq!(p.frame.volume.fog_marched, 1);
        // The fog's ribbons are as wide as the objects' light-view texels.
        assert!((g.ribbon_half_width - o.texel_area.sqrt()).abs() < 1e-6);
        w.object_light_current = true;
        assert!(!plan(&s, &w, 1.0).object_light.unwrap().due);
    }
}
