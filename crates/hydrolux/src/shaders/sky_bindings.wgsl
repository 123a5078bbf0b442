// The sky as seen by render passes (group 0, after `frame`).
#import sky_model
@group(0) @binding(1) var<uniform> sky: SkyParams;
@group(0) @binding(2) var sky_cube: texture_cube<f32>;
@group(0) @binding(3) var sky_sampler: sampler;
