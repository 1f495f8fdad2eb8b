// Unlit palette shader: the colour of a fragment is the palette colour of the
// texel its interpolated UV falls in. For the canonical palette the colour is
// computed (index = y * W + x, r = index >> 16, g = (index >> 8) & 255,
// b = index & 255); an external palette is read with textureLoad (no
// filtering, no mipmaps). Occluders are drawn in the background colour.
//
// Exact for any mesh by construction: every vertex also carries its
// triangle's three corners in texel coordinates (the triangle's chart), passed
// flat, and the fragment's point is rebuilt from barycentrics clamped to the
// triangle (each >= 0, summing to 1), so it lies on the closed chart triangle.
// The rasteriser's barycentrics of a sliver, or of a zero-area triangle that
// f32 snapping turned into a sliver, can be far outside [0, 1]; after the
// clamp the texel touches the chart (up to f32 rounding, far below a texel),
// and the PIdT labels every texel within one texel of the chart.

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
    // Barycentric weights of corners 1 and 2 (corner 0 has the rest),
    // interpolated perspective-correctly as the UV would be.
    @location(0) weights: vec2<f32>,
    @location(1) @interpolate(flat) chart0: vec2<f32>,
    @location(2) @interpolate(flat) chart1: vec2<f32>,
    @location(3) @interpolate(flat) chart2: vec2<f32>,
};

@vertex
fn vs_main(
    @builtin(vertex_index) index: u32,
    @location(0) position: vec3<f32>,
    @location(2) chart0: vec2<f32>,
    @location(3) chart1: vec2<f32>,
    @location(4) chart2: vec2<f32>,
) -> VertexOut {
    var out: VertexOut;
    out.position = u.clip_from_model * vec4<f32>(position, 1.0);
    // Triangles are drawn unindexed from vertex 0, three vertices each.
    let corner = index % 3u;
    out.weights = vec2<f32>(select(0.0, 1.0, corner == 1u), select(0.0, 1.0, corner == 2u));
    out.chart0 = chart0;
    out.chart1 = chart1;
    out.chart2 = chart2;
    return out;
}

fn unpack(packed: u32) -> vec4<f32> {
    // k / 255 converts back to exactly k in an Rgba8Unorm target. Alpha is
    // 255 minus the id's high byte (32-bit texel ids, palettes above 2^24
    // texels): 255, opaque, for every id below 2^24.
    let alpha = f32(255u - (packed >> 24u));
    return vec4<f32>(f32((packed >> 16u) & 255u), f32((packed >> 8u) & 255u), f32(packed & 255u), alpha) / 255.0;
}

// The point of the closed chart triangle c0-c1-c2 with barycentric weights
// w (of c1 and c2), clamped to the triangle; a non-finite w gives c0.
fn on_chart(w: vec2<f32>, c0: vec2<f32>, c1: vec2<f32>, c2: vec2<f32>) -> vec2<f32> {
    if (!(all(abs(w) < vec2<f32>(1e30)))) {
        return c0;
    }
    var clamped = max(w, vec2<f32>(0.0));
    let sum = clamped.x + clamped.y;
    if (sum > 1.0) {
        clamped = clamped / sum;
    }
    return c0 + clamped.x * (c1 - c0) + clamped.y * (c2 - c0);
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
    let p = on_chart(in.weights, in.chart0, in.chart1, in.chart2);
    // The chart's texel rectangle bounds the result whatever the rounding.
    let low = floor(min(in.chart0, min(in.chart1, in.chart2)));
    let high = floor(max(in.chart0, max(in.chart1, in.chart2)));
    let in_chart = clamp(floor(p), low, high);
    let texel = vec2<u32>(clamp(in_chart, vec2<f32>(0.0), size - vec2<f32>(1.0)));
    if (u.mode == MODE_EXTERNAL_PALETTE) {
        return textureLoad(palette_texture, vec2<i32>(texel), 0);
    }
    return unpack(texel.y * u.palette.x + texel.x);
}
