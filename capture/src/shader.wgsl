// Unlit palette shader: the colour of a fragment is the palette colour of the
// texel its interpolated UV falls in. For the canonical palette the colour is
// computed (index = y * W + x, r = index >> 16, g = (index >> 8) & 255,
// b = index & 255); an external palette is read with textureLoad (no
// filtering, no mipmaps). Occluders are drawn in the background colour.

struct Uniforms {
    clip_from_model: mat4x4<f32>,
    palette: vec2<u32>,
    // 0: canonical palette, 1: external palette texture, 2: background colour.
    mode: u32,
    background: u32,
};

@group(0) @binding(0) var<uniform> u: Uniforms;
@group(0) @binding(1) var palette_texture: texture_2d<f32>;

struct VertexOut {
    @builtin(position) position: vec4<f32>,
    @location(0) uv: vec2<f32>,
};

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) uv: vec2<f32>) -> VertexOut {
    var out: VertexOut;
    out.position = u.clip_from_model * vec4<f32>(position, 1.0);
    out.uv = uv;
    return out;
}

fn unpack(packed: u32) -> vec4<f32> {
    // k / 255 converts back to exactly k in an Rgba8Unorm target.
    return vec4<f32>(f32((packed >> 16u) & 255u), f32((packed >> 8u) & 255u), f32(packed & 255u), 255.0) / 255.0;
}

// Draw modes, the same numbers as `draw_mode` in render.rs (change both together).
const MODE_EXTERNAL_PALETTE: u32 = 1u;
const MODE_BACKGROUND: u32 = 2u;

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    if (u.mode == MODE_BACKGROUND) {
        return unpack(u.background);
    }
    let size = vec2<f32>(u.palette);
    let texel = vec2<u32>(clamp(floor(in.uv * size), vec2<f32>(0.0), size - vec2<f32>(1.0)));
    if (u.mode == MODE_EXTERNAL_PALETTE) {
        return textureLoad(palette_texture, vec2<i32>(texel), 0);
    }
    return unpack(texel.y * u.palette.x + texel.x);
}
