// The exact "unobstructed" measure on the GPU: the test of
// `unobstructed::unobstructed` and the segment queries of `ray_bvh`, step for
// step in f64 (SHADER_F64), one invocation per surface point, looping over
// every eye-frame. Any change here must be made there too: the tests compare
// both on every sampled point.

struct Params {
    // First point of this dispatch, points in all, eye-frames.
    first_point: u32,
    point_count: u32,
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
    _pad0: u32,
    _pad1: u32,
};

@group(0) @binding(0) var<uniform> params: Params;
// Per point: position xyz, normal xyz.
@group(0) @binding(1) var<storage, read> points: array<f64>;
// Per eye-frame (40): eye in vehicle xyz, eye xyz, to_world (16, column-major),
// view_proj (16, column-major), the surface offset, 1 unused.
@group(0) @binding(2) var<storage, read> eye_frames: array<f64>;
// Node bounds (6 per node: min xyz, max xyz) of both hierarchies, then their
// triangles (9 per triangle).
@group(0) @binding(3) var<storage, read> geometry: array<f64>;
// Per node: first, count (count 0: inner node, children at first, first + 1).
@group(0) @binding(4) var<storage, read> nodes: array<u32>;
@group(0) @binding(5) var<storage, read_write> counts: array<u32>;

const STACK: u32 = 64u;

fn point_vec(base: u32) -> vec3<f64> {
    return vec3<f64>(points[base], points[base + 1u], points[base + 2u]);
}

fn eye_vec(base: u32) -> vec3<f64> {
    return vec3<f64>(eye_frames[base], eye_frames[base + 1u], eye_frames[base + 2u]);
}

fn geometry_vec(base: u32) -> vec3<f64> {
    return vec3<f64>(geometry[base], geometry[base + 1u], geometry[base + 2u]);
}

// Column-major 4×4 at `base` times (p, 1): as glam's DMat4 * DVec4.
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
        if (low > high) {
            return false;
        }
    }
    return true;
}

// Möller–Trumbore, segment parameter strictly inside (0, 1).
fn segment_hits_triangle(origin: vec3<f64>, direction: vec3<f64>, base: u32) -> bool {
    let t0 = geometry_vec(base);
    let e1 = geometry_vec(base + 3u) - t0;
    let e2 = geometry_vec(base + 6u) - t0;
    let p = cross(direction, e2);
    let determinant = dot(e1, p);
    if (abs(determinant) < 1e-15lf) {
        return false;
    }
    let inverse = 1.0lf / determinant;
    let s = origin - t0;
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

// Does the open segment from → to cross a triangle of one hierarchy?
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

@compute @workgroup_size(64)
fn count_points(@builtin(global_invocation_id) id: vec3<u32>) {
    let index = params.first_point + id.x;
    if (index >= params.point_count) {
        return;
    }
    let position = point_vec(index * 6u);
    let normal = point_vec(index * 6u + 3u);
    var seen = 0u;
    for (var e = 0u; e < params.eye_frame_count; e++) {
        let base = e * 40u;
        let offset = eye_frames[base + 38u];
        let eye_in_vehicle = eye_vec(base);
        let towards_eye = eye_in_vehicle - position;
        let side = dot(normal, towards_eye);
        // Edge-on within 1e-9 rad: EDGE_ON_SQUARED, compared as on the CPU.
        if (side * side <= 1e-18lf * dot(towards_eye, towards_eye)) {
            continue;
        }
        let world = transform(base + 6u, position);
        let clip = transform(base + 22u, world.xyz);
        let in_view = clip.w > 0.0lf && abs(clip.x) <= clip.w && abs(clip.y) <= clip.w
            && clip.z >= 0.0lf && clip.z <= clip.w;
        if (!in_view) {
            continue;
        }
        let lifted = position + normal * (offset * sign(side));
        let lifted_world = transform(base + 6u, lifted).xyz;
        if (blocks(lifted, eye_in_vehicle, 0u, params.vehicle_node_count, params.vehicle_nodes, params.vehicle_triangles)) {
            continue;
        }
        if (blocks(lifted_world, eye_vec(base + 3u), params.world_node_base, params.world_node_count, params.world_nodes, params.world_triangles)) {
            continue;
        }
        seen += 1u;
    }
    counts[index] = seen;
}
