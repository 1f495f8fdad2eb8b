// The exact measure on the GPU: the rules of `unobstructed/rules.rs` and the
// segment queries of `unobstructed/bvh.rs`, step for step in f64
// (SHADER_F64), one invocation per sampled texel, looping over every
// eye-frame and, inside it, over the texel's samples — the order of
// `unobstructed/cpu.rs`. Any change here must be made there too: the tests
// compare both on every sampled texel.

struct Params {
    // First texel of this dispatch, texels in all, eye-frames.
    first_texel: u32,
    texel_count: u32,
    eye_frame_count: u32,
    // Where each part of `geometry` starts (in f64s), and the nodes of the
    // world hierarchy in `nodes` (in nodes).
    vehicle_nodes: u32,
    world_nodes: u32,
    vehicle_triangles: u32,
    world_triangles: u32,
    world_node_base: u32,
    vehicle_node_count: u32,
    world_node_count: u32,
    // Moving occluders, and f64s per eye-frame (40 + 16 per moving occluder).
    moving_count: u32,
    eye_frame_words: u32,
};

@group(0) @binding(0) var<uniform> params: Params;
// Per sampled texel: first sample, samples, part, unused.
@group(0) @binding(1) var<storage, read> texels: array<u32>;
// Per sample (8): position xyz, normal xyz, area m², edge-on tolerance m.
@group(0) @binding(2) var<storage, read> samples: array<f64>;
// Per eye-frame (40 + 16 per moving occluder): eye in vehicle xyz, eye local
// xyz, vehicle → local (16, column-major), vehicle → clip (16, column-major),
// the eye's w − z, the lift, then local → each moving occluder's own frame
// (16 each, column-major).
@group(0) @binding(3) var<storage, read> eye_frames: array<f64>;
// Node bounds (6 per node: min xyz, max xyz) of both hierarchies, then their
// triangles (9 per triangle: corner, edge 1, edge 2).
@group(0) @binding(4) var<storage, read> geometry: array<f64>;
// Per node: first, count (count 0: inner node, children at first, first + 1).
@group(0) @binding(5) var<storage, read> nodes: array<u32>;
@group(0) @binding(6) var<storage, read_write> counts: array<u32>;
@group(0) @binding(7) var<storage, read_write> solid_angles: array<f64>;
// One bit per (part, eye-frame): part * eye_frame_count + eye-frame.
@group(0) @binding(8) var<storage, read_write> part_seen: array<atomic<u32>>;
// Per moving occluder (4): its hierarchy's node base and node count in
// `nodes`, and where its bounds and triangles start in `geometry`.
@group(0) @binding(9) var<storage, read> moving: array<u32>;

// TRAVERSAL_STACK in bvh.rs.
const STACK: u32 = 64u;
// EDGE_ON_RELATIVE in types.rs.
const EDGE_ON_RELATIVE: f64 = 1e-6lf;

fn sample_vec(base: u32) -> vec3<f64> {
    return vec3<f64>(samples[base], samples[base + 1u], samples[base + 2u]);
}

fn eye_vec(base: u32) -> vec3<f64> {
    return vec3<f64>(eye_frames[base], eye_frames[base + 1u], eye_frames[base + 2u]);
}

fn geometry_vec(base: u32) -> vec3<f64> {
    return vec3<f64>(geometry[base], geometry[base + 1u], geometry[base + 2u]);
}

// Column-major 4×4 at `base` times (p, 1), column by column: `transform_point`.
fn transform(base: u32, p: vec3<f64>) -> vec4<f64> {
    var out = vec4<f64>(0.0lf, 0.0lf, 0.0lf, 0.0lf);
    for (var row = 0u; row < 4u; row++) {
        out[row] = eye_frames[base + row] * p.x + eye_frames[base + 4u + row] * p.y
            + eye_frames[base + 8u + row] * p.z + eye_frames[base + 12u + row];
    }
    return out;
}

// Slab test of the segment from + s·direction, s ∈ [0, 1], against a box.
fn segment_hits_box(origin: vec3<f64>, direction: vec3<f64>, node_base: u32) -> bool {
    let lo = geometry_vec(node_base);
    let hi = geometry_vec(node_base + 3u);
    var low = 0.0lf;
    var high = 1.0lf;
    for (var axis = 0u; axis < 3u; axis++) {
        if (direction[axis] == 0.0lf) {
            if (origin[axis] < lo[axis] || origin[axis] > hi[axis]) {
                return false;
            }
            continue;
        }
        let inverse = 1.0lf / direction[axis];
        let a = (lo[axis] - origin[axis]) * inverse;
        let b = (hi[axis] - origin[axis]) * inverse;
        low = max(low, min(a, b));
        high = min(high, max(a, b));
        // Conservative as bvh.rs's SLAB_ROUNDING (the bounds are widened too).
        if (low > high * 1.0000000000000007lf) {
            return false;
        }
    }
    return true;
}

// Möller–Trumbore, segment parameter strictly inside (1e-9, 1 − 1e-9).
fn segment_hits_triangle(origin: vec3<f64>, direction: vec3<f64>, base: u32) -> bool {
    let corner = geometry_vec(base);
    let e1 = geometry_vec(base + 3u);
    let e2 = geometry_vec(base + 6u);
    let p = cross(direction, e2);
    let determinant = dot(e1, p);
    if (abs(determinant) < 1e-15lf) {
        return false;
    }
    let inverse = 1.0lf / determinant;
    let s = origin - corner;
    let u = dot(s, p) * inverse;
    if (u < 0.0lf || u > 1.0lf) {
        return false;
    }
    let q = cross(s, e1);
    let v = dot(direction, q) * inverse;
    if (v < 0.0lf || u + v > 1.0lf) {
        return false;
    }
    let along = dot(e2, q) * inverse;
    return along > 1e-9lf && along < 1.0lf - 1e-9lf;
}

// Does the open segment from → to cross a triangle of one hierarchy? Any hit ends the walk.
fn blocks(origin: vec3<f64>, to: vec3<f64>, node_base: u32, node_count: u32, bounds: u32, triangles: u32) -> bool {
    if (node_count == 0u) {
        return false;
    }
    let direction = to - origin;
    var stack: array<u32, 64>;
    var top = 1u;
    stack[0] = 0u;
    while (top > 0u) {
        top -= 1u;
        let node = stack[top];
        if (!segment_hits_box(origin, direction, bounds + node * 6u)) {
            continue;
        }
        let first = nodes[2u * (node_base + node)];
        let count = nodes[2u * (node_base + node) + 1u];
        if (count > 0u) {
            for (var t = first; t < first + count; t++) {
                if (segment_hits_triangle(origin, direction, triangles + t * 9u)) {
                    return true;
                }
            }
        } else if (top + 2u <= STACK) {
            stack[top] = first;
            stack[top + 1u] = first + 1u;
            top += 2u;
        }
    }
    return false;
}

// The solid angle (sr) of sample `s` in eye-frame `e`, or a negative number
// when it is not visible: `visible_solid_angle` in rules.rs.
fn visible_solid_angle(s: u32, e: u32) -> f64 {
    let base = e * params.eye_frame_words;
    let position = sample_vec(s * 8u);
    let normal = sample_vec(s * 8u + 3u);
    let eye_in_vehicle = eye_vec(base);
    let towards_eye = eye_in_vehicle - position;
    let distance_squared = dot(towards_eye, towards_eye);
    let distance = sqrt(distance_squared);
    let side = dot(normal, towards_eye);
    if (abs(side) <= EDGE_ON_RELATIVE * distance + samples[s * 8u + 7u]) {
        return -1.0lf;
    }
    let clip = transform(base + 22u, position);
    let in_view = clip.w > 0.0lf && abs(clip.x) <= clip.w && abs(clip.y) <= clip.w
        && clip.z >= 0.0lf && clip.z <= clip.w;
    if (!in_view) {
        return -1.0lf;
    }
    let lifted = position + normal * (eye_frames[base + 39u] * sign(side));
    let margin = clip.w - clip.z;
    let to_near = margin / (margin - eye_frames[base + 38u]);
    let end = lifted + (eye_in_vehicle - lifted) * to_near;
    if (blocks(lifted, end, 0u, params.vehicle_node_count, params.vehicle_nodes, params.vehicle_triangles)) {
        return -1.0lf;
    }
    let lifted_local = transform(base + 6u, lifted).xyz;
    let end_local = lifted_local + (eye_vec(base + 3u) - lifted_local) * to_near;
    if (blocks(lifted_local, end_local, params.world_node_base, params.world_node_count, params.world_nodes, params.world_triangles)) {
        return -1.0lf;
    }
    // Moving occluders: the same segment in each one's own frame.
    for (var k = 0u; k < params.moving_count; k++) {
        let to_own = base + 40u + k * 16u;
        let start = transform(to_own, lifted_local).xyz;
        let stop = transform(to_own, end_local).xyz;
        if (blocks(start, stop, moving[k * 4u], moving[k * 4u + 1u], moving[k * 4u + 2u], moving[k * 4u + 3u])) {
            return -1.0lf;
        }
    }
    return samples[s * 8u + 6u] * abs(side) / (distance_squared * distance);
}

@compute @workgroup_size(64)
fn count_texels(@builtin(global_invocation_id) id: vec3<u32>) {
    let index = params.first_texel + id.x;
    if (index >= params.texel_count) {
        return;
    }
    let first = texels[index * 4u];
    let count = texels[index * 4u + 1u];
    let part = texels[index * 4u + 2u];
    var seen_frames = 0u;
    var solid = 0.0lf;
    for (var e = 0u; e < params.eye_frame_count; e++) {
        var seen = false;
        for (var s = first; s < first + count; s++) {
            let solid_angle = visible_solid_angle(s, e);
            if (solid_angle >= 0.0lf) {
                seen = true;
                solid += solid_angle;
            }
        }
        if (seen) {
            seen_frames += 1u;
            let bit = part * params.eye_frame_count + e;
            atomicOr(&part_seen[bit / 32u], 1u << (bit % 32u));
        }
    }
    counts[index] = seen_frames;
    solid_angles[index] = solid;
}
