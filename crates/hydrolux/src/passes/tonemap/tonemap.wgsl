// Output: filmic tone map of the pre-exposed HDR image into the target, or
// one of the debug views (frame.modes.debug_view) instead: the reflection or
// refraction texture (tone mapped), the depth buffer (log distance), world
// normals (written raw by the geometry and water shaders), the sun's
// shadow map, each pixel's medium (the stencil), or the floor caustic map. frame.modes.tonemap: 0 ACES, 1 clamp. If the target is not an sRGB
// format the transfer curve is applied here (OUTPUT_SRGB_CURVE prepended).
#import constants, frame, fullscreen, tonemap_curve, caustics_lookup, shadow_lookup

// The sun's shadow map as plain depth, for its view.
@group(2) @binding(0) var shadow_depth: texture_2d<f32>;
@group(1) @binding(0) var hdr: texture_2d<f32>;
@group(1) @binding(1) var reflection_tex: texture_2d<f32>;
@group(1) @binding(2) var refraction_tex: texture_2d<f32>;
@group(1) @binding(3) var depth_tex: texture_2d<f32>;
@group(1) @binding(4) var medium_tex: texture_2d<u32>;
// Bilinear, for filtering a frame drawn smaller than the output.
@group(1) @binding(5) var hdr_sampler: sampler;

@vertex
fn vs_main(@builtin(vertex_index) i: u32) -> @builtin(position) vec4<f32> {
    return vec4<f32>(fullscreen_ndc(i), 0.0, 1.0);
}

fn tone(c: vec3<f32>) -> vec3<f32> {
    if (frame.modes.tonemap == TONEMAP_ACES) {
        return aces_filmic(c);
    }
    return clamp(c, vec3<f32>(0.0), vec3<f32>(1.0));
}

// The output's size: the caller's target, which the frame (frame.view.size)
// may be smaller than (render.quality).
fn output_size() -> vec2<f32> {
    if (frame.modes.output_width == 0u) {
        return frame.view.size;
    }
    return vec2<f32>(f32(frame.modes.output_width), f32(frame.modes.output_height));
}

// A square texture letterboxed into the output: its coordinates here.
fn letterbox(pos: vec2<f32>) -> vec2<f32> {
    let size = output_size();
    let side = min(size.x, size.y);
    return (pos - 0.5 * (size - side)) / side;
}

// The texel of a texture of another size under this output pixel.
fn scaled_texel(pos: vec2<f32>, dims: vec2<u32>) -> vec2<i32> {
    return vec2<i32>(pos * vec2<f32>(dims) / output_size());
}

// The frame's HDR colour under this output pixel: bilinear when the frame is
// smaller than the output (render.quality), else the pixel itself.
fn hdr_at(pos: vec2<f32>) -> vec3<f32> {
    let dims = vec2<i32>(textureDimensions(hdr));
    let out = output_size();
    if (all(vec2<f32>(dims) == out)) {
        return textureLoad(hdr, vec2<i32>(pos), 0).rgb;
    }
    return textureSampleLevel(hdr, hdr_sampler, pos / out, 0.0).rgb;
}

// The frame's texel (same size as the HDR image) under this output pixel.
fn frame_texel(pos: vec2<f32>) -> vec2<i32> {
    return scaled_texel(pos, textureDimensions(hdr));
}

@fragment
fn fs_main(@builtin(position) pos: vec4<f32>) -> @location(0) vec4<f32> {
    var mapped: vec3<f32>;
    switch (frame.modes.debug_view) {
        case VIEW_REFLECTION: {
            mapped = tone(textureLoad(reflection_tex, scaled_texel(pos.xy, textureDimensions(reflection_tex)), 0).rgb);
        }
        case VIEW_REFRACTION: {
            mapped = tone(textureLoad(refraction_tex, scaled_texel(pos.xy, textureDimensions(refraction_tex)), 0).rgb);
        }
        case VIEW_NORMALS, VIEW_RIPPLES, VIEW_FOAM, VIEW_FRESNEL: {
            mapped = hdr_at(pos.xy);
        }
        case VIEW_DEPTH: {
            // Reversed-Z with an infinite far plane: d = near / distance.
            // White at 0.5 m fading logarithmically to black at 2 km; sky black.
            let d = textureLoad(depth_tex, frame_texel(pos.xy), 0).r;
            var g = 0.0;
            if (d > 0.0) {
                g = clamp(1.0 - log2((0.05 / d) / 0.5) / 12.0, 0.0, 1.0);
            }
            mapped = vec3<f32>(g);
        }
        case VIEW_SHADOW: {
            mapped = vec3<f32>(0.0, 0.0, 0.15);
            let uv = letterbox(pos.xy);
            if (all(uv >= vec2<f32>(0.0)) && all(uv < vec2<f32>(1.0))) {
                let dims = vec2<f32>(textureDimensions(shadow_depth));
                mapped = vec3<f32>(1.0 - textureLoad(shadow_depth, vec2<i32>(uv * dims), 0).r);
            }
        }
        case VIEW_CAUSTICS: {
            // Relative floor irradiance: the flat-water value is mid grey.
            mapped = vec3<f32>(0.0, 0.0, 0.15);
            let uv = letterbox(pos.xy);
            if (all(uv >= vec2<f32>(0.0)) && all(uv < vec2<f32>(1.0))) {
                // The floor layer (the deepest).
                let dims = vec2<f32>(textureDimensions(caustic_map));
                let floor_layer = i32(frame.caustics.layers) - 1;
                let c = textureLoad(caustic_map, vec2<i32>(uv * dims), floor_layer, 0).r * frame.caustics.inv_flat_value;
                mapped = vec3<f32>(0.5 * c);
            }
        }
        case VIEW_MEDIUM: {
            // The final image tinted by the pixel's medium: air warm, water blue.
            let water = textureLoad(medium_tex, frame_texel(pos.xy), 0).r == STENCIL_WATER;
            let tint = select(vec3<f32>(1.0, 0.85, 0.4), vec3<f32>(0.1, 0.4, 1.0), water);
            mapped = mix(tone(hdr_at(pos.xy)), tint, 0.5);
        }
        default: {
            mapped = tone(hdr_at(pos.xy));
        }
    }
    if (OUTPUT_SRGB_CURVE) {
        mapped = linear_to_srgb(mapped);
    }
    return vec4<f32>(mapped, 1.0);
}
