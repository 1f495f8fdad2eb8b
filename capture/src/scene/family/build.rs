//! The mesh of a laid-out body: the lower body (front, rear, sides cut
//! around the wheel arches), the greenhouse (windshield with its rails,
//! roof, side windows and B-pillars, rear window), the pickup's bed, the
//! trim that stands proud (bumpers, grill, lights, plates, mirrors) and the
//! wheels. Every panel is a planar quad given with the side it faces
//! ([`facing`]); panels in one plane meet along edges only, which the
//! family's tests check triangle by triangle, and every edge that runs past
//! another panel's corner is split there ([`split_t_junctions`]), so that
//! no pixel falls through a crack into the body.

use glam::{Vec3, vec3};

use crate::scene::family::BodyType;
use crate::scene::family::layout::{BUMPER_DEPTH_M, GREENHOUSE_INSET_M, Layout, PLATE_DEPTH_M};
use crate::scene::mesh::Mesh;
use crate::scene::shapes::{WheelSize, facing, split_t_junctions, wheel};

/// Per side: the suffix of its parts and the sign of y.
const SIDES: [(&str, f64); 2] = [("left", 1.0), ("right", -1.0)];
/// The windshield rails' (A-pillars') width, metres.
const RAIL_M: f64 = 0.08;

fn v(x: f64, y: f64, z: f64) -> Vec3 {
    vec3(x as f32, y as f32, z as f32)
}

/// All six faces of a box but those `None`, each naming `name`.
fn trim(m: &mut Mesh, min: Vec3, max: Vec3, name: &str, leave_out: usize) {
    let mut faces = [Some(name); 6];
    faces[leave_out] = None;
    m.add_box(min, max, faces);
}

/// Face indices of [`Mesh::add_box`].
const PLUS_X: usize = 0;
const MINUS_X: usize = 1;
const PLUS_Y: usize = 2;
const MINUS_Y: usize = 3;

/// The body's mesh.
pub(crate) fn mesh(l: &Layout) -> Mesh {
    let mut m = Mesh::default();
    front(&mut m, l);
    rear(&mut m, l);
    sides(&mut m, l);
    greenhouse(&mut m, l);
    if l.body == BodyType::Pickup {
        bed(&mut m, l);
    }
    wheels_and_mirrors(&mut m, l);
    split_t_junctions(&mut m);
    m
}

/// Heights on the front and rear faces, as shares of the panel between the
/// clearance and the belt: (bottom, top).
struct Bands {
    bumper_top: f64,
    plate: [f64; 2],
    grill: [f64; 2],
    lights: [f64; 2],
}

fn bands(l: &Layout) -> Bands {
    let c = l.proportions.clearance_m;
    let panel = l.dims.bonnet_height_m - c;
    let at = |share: f64| c + share * panel;
    Bands {
        bumper_top: at(0.3),
        plate: [at(0.06), at(0.24)],
        grill: [at(0.38), at(0.9)],
        lights: [at(0.6), at(0.94)],
    }
}

fn front(m: &mut Mesh, l: &Layout) {
    let (c, bh, hw, w) = (l.proportions.clearance_m, l.dims.bonnet_height_m, l.half_width, l.dims.width_m);
    let xg = l.front_face;
    let b = bands(l);
    facing(
        m,
        "hood",
        [v(l.windshield_base, -hw, bh), v(xg, -hw, bh), v(xg, hw, bh), v(l.windshield_base, hw, bh)],
        Vec3::Z,
    );
    facing(m, "grill", [v(xg, -hw, c), v(xg, hw, c), v(xg, hw, bh), v(xg, -hw, bh)], Vec3::X);
    let bumper = Some("front_bumper");
    m.add_box(
        v(xg, -hw, c),
        v(xg + BUMPER_DEPTH_M, hw, b.bumper_top),
        [bumper, None, bumper, bumper, bumper, None],
    );
    trim(m, v(xg, -0.28 * w, b.grill[0]), v(xg + 0.02, 0.28 * w, b.grill[1]), "grill", MINUS_X);
    for (side, s) in SIDES {
        let (y0, y1) = ordered(0.3 * w * s, 0.45 * w * s);
        trim(m, v(xg, y0, b.lights[0]), v(xg + 0.03, y1, b.lights[1]), &format!("headlight_{side}"), MINUS_X);
    }
    let plate = (0.2 * w).min(0.26);
    let x = l.half_length - PLATE_DEPTH_M;
    trim(m, v(x, -plate, b.plate[0]), v(l.half_length, plate, b.plate[1]), "front_license_plate", MINUS_X);
}

fn rear(m: &mut Mesh, l: &Layout) {
    let (c, bh, hw, w) = (l.proportions.clearance_m, l.dims.bonnet_height_m, l.half_width, l.dims.width_m);
    let xr = l.rear_face;
    let b = bands(l);
    let panel = match l.body {
        BodyType::Sedan | BodyType::Bus => "rear_panel",
        BodyType::Suv | BodyType::Pickup => "tailgate",
        BodyType::Van => "rear_doors",
    };
    facing(m, panel, [v(xr, -hw, c), v(xr, hw, c), v(xr, hw, bh), v(xr, -hw, bh)], -Vec3::X);
    if l.body == BodyType::Sedan {
        let deck = l.greenhouse_rear[0];
        facing(m, "trunk_lid", [v(xr, -hw, bh), v(deck, -hw, bh), v(deck, hw, bh), v(xr, hw, bh)], Vec3::Z);
    }
    let bumper = Some("rear_bumper");
    m.add_box(
        v(xr - BUMPER_DEPTH_M, -hw, c),
        v(xr, hw, b.bumper_top),
        [None, bumper, bumper, bumper, bumper, None],
    );
    for (side, s) in SIDES {
        let (y0, y1) = ordered(0.3 * w * s, 0.45 * w * s);
        trim(m, v(xr - 0.03, y0, b.lights[0]), v(xr, y1, b.lights[1]), &format!("tail_light_{side}"), PLUS_X);
    }
    let plate = (0.2 * w).min(0.26);
    let x = -l.half_length + PLATE_DEPTH_M;
    trim(m, v(-l.half_length, -plate, b.plate[0]), v(x, plate, b.plate[1]), "rear_license_plate", PLUS_X);
}

fn ordered(a: f64, b: f64) -> (f64, f64) {
    (a.min(b), a.max(b))
}

/// The lower body's side sections from the rear face forward: (part, rear x, front x).
fn sections(l: &Layout, side: &str) -> Vec<(String, f64, f64)> {
    let (xr, x0, xg) = (l.rear_face, l.windshield_base, l.front_face);
    let door_split = l.pillar[1] - 0.05;
    let named = |name: &str| format!("{name}_{side}");
    let mut list = vec![(named("front_fender"), x0, xg)];
    let rear = match l.body {
        BodyType::Sedan | BodyType::Suv => "quarter_panel",
        BodyType::Van => "side_panel",
        BodyType::Pickup => "bed_side",
        BodyType::Bus => {
            if side == "right" {
                list.push((named("door_front"), door_split, x0));
                list.push((named("side_panel"), xr, door_split));
            } else {
                list.push((named("side_panel"), xr, x0));
            }
            return list;
        }
    };
    list.push((named("door_front"), door_split, x0));
    list.push((named("door_rear"), l.rear_door_end, door_split));
    list.push((named(rear), xr, l.rear_door_end));
    list
}

/// The sides below the belt, cut around the wheel arches (their panels
/// are the fenders), the arches' liners, and the shelf along the belt
/// outside the greenhouse.
fn sides(m: &mut Mesh, l: &Layout) {
    let (c, bh, hw) = (l.proportions.clearance_m, l.dims.bonnet_height_m, l.half_width);
    let arches = l.arches();
    for (side, s) in SIDES {
        let out = Vec3::Y * s as f32;
        let list = sections(l, side);
        let mut breaks: Vec<f64> =
            list.iter().flat_map(|&(_, a, b)| [a, b]).chain(arches.iter().flatten().copied()).collect();
        breaks.sort_by(f64::total_cmp);
        breaks.dedup();
        let y = hw * s;
        for pair in breaks.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            let mid = (a + b) / 2.0;
            let Some((name, _, _)) = list.iter().find(|(_, x0, x1)| (*x0..=*x1).contains(&mid)) else {
                continue;
            };
            let arch = arches.iter().position(|[x0, x1]| (*x0..=*x1).contains(&mid));
            let (name, bottom) = match arch {
                Some(0) => (format!("front_fender_{side}"), l.arch_top),
                Some(_) => (format!("rear_fender_{side}"), l.arch_top),
                None => (name.clone(), c),
            };
            facing(m, &name, [v(a, y, bottom), v(b, y, bottom), v(b, y, bh), v(a, y, bh)], out);
        }
        let inner = (hw - l.arch_depth()) * s;
        for (axle, [a, b]) in ["front", "rear"].into_iter().zip(arches) {
            let name = format!("wheel_arch_{axle}_{side}");
            let top = l.arch_top;
            facing(m, &name, [v(a, inner, top), v(b, inner, top), v(b, y, top), v(a, y, top)], -Vec3::Z);
            facing(m, &name, [v(a, inner, c), v(a, y, c), v(a, y, top), v(a, inner, top)], Vec3::X);
            facing(m, &name, [v(b, inner, c), v(b, y, c), v(b, y, top), v(b, inner, top)], -Vec3::X);
            facing(m, &name, [v(a, inner, c), v(b, inner, c), v(b, inner, top), v(a, inner, top)], out);
        }
        let gy = (hw - GREENHOUSE_INSET_M) * s;
        let x0 = l.windshield_base;
        let back = l.greenhouse_rear[0];
        facing(m, "cab_shoulder", [v(back, gy, bh), v(x0, gy, bh), v(x0, y, bh), v(back, y, bh)], Vec3::Z);
    }
}

/// Windshield and rails, roof, rear window, and per side the front window,
/// the B-pillar and the rear window.
fn greenhouse(m: &mut Mesh, l: &Layout) {
    let (bh, h) = (l.dims.bonnet_height_m, l.dims.height_m);
    let gw = l.half_width - GREENHOUSE_INSET_M;
    let (x0, x1) = (l.windshield_base, l.windshield_top);
    for (name, y0, y1) in [
        ("windshield_rail_right", -gw, -gw + RAIL_M),
        ("windshield", -gw + RAIL_M, gw - RAIL_M),
        ("windshield_rail_left", gw - RAIL_M, gw),
    ] {
        facing(m, name, [v(x0, y0, bh), v(x0, y1, bh), v(x1, y1, h), v(x1, y0, h)], vec3(1.0, 0.0, 1.0));
    }
    let [back0, back1] = l.greenhouse_rear;
    facing(m, "roof", [v(back1, -gw, h), v(x1, -gw, h), v(x1, gw, h), v(back1, gw, h)], Vec3::Z);
    facing(
        m,
        "rear_window",
        [v(back0, -gw, bh), v(back0, gw, bh), v(back1, gw, h), v(back1, -gw, h)],
        vec3(-1.0, 0.0, 1.0),
    );
    let [p0, p1] = l.pillar;
    for (side, s) in SIDES {
        let y = gw * s;
        let out = Vec3::Y * s as f32;
        facing(
            m,
            &format!("window_front_{side}"),
            [v(p1, y, bh), v(x0, y, bh), v(x1, y, h), v(p1, y, h)],
            out,
        );
        facing(m, &format!("b_pillar_{side}"), [v(p0, y, bh), v(p1, y, bh), v(p1, y, h), v(p0, y, h)], out);
        facing(
            m,
            &format!("window_rear_{side}"),
            [v(back0, y, bh), v(p0, y, bh), v(p0, y, h), v(back1, y, h)],
            out,
        );
    }
}

/// The pickup's open bed behind the cab: floor, inner walls, the
/// tailgate's inside and top, and the rails along its sides.
fn bed(m: &mut Mesh, l: &Layout) {
    let (bh, zf, t) = (l.dims.bonnet_height_m, l.bed_floor, GREENHOUSE_INSET_M);
    let inner = l.half_width - t;
    let (back, cab) = (l.rear_face + t, l.rear_door_end);
    facing(
        m,
        "truck_bed",
        [v(back, -inner, zf), v(cab, -inner, zf), v(cab, inner, zf), v(back, inner, zf)],
        Vec3::Z,
    );
    facing(
        m,
        "truck_bed",
        [v(cab, -inner, zf), v(cab, inner, zf), v(cab, inner, bh), v(cab, -inner, bh)],
        -Vec3::X,
    );
    facing(
        m,
        "tailgate",
        [v(back, -inner, zf), v(back, inner, zf), v(back, inner, bh), v(back, -inner, bh)],
        Vec3::X,
    );
    let xr = l.rear_face;
    facing(
        m,
        "tailgate",
        [v(xr, -inner, bh), v(back, -inner, bh), v(back, inner, bh), v(xr, inner, bh)],
        Vec3::Z,
    );
    for (_, s) in SIDES {
        let y = inner * s;
        let edge = l.half_width * s;
        let into_bed = -Vec3::Y * s as f32;
        facing(m, "truck_bed", [v(back, y, zf), v(cab, y, zf), v(cab, y, bh), v(back, y, bh)], into_bed);
        facing(m, "bed_rail", [v(xr, y, bh), v(cab, y, bh), v(cab, edge, bh), v(xr, edge, bh)], Vec3::Z);
    }
}

/// Tyres and rims 2 cm inside the body's sides (in the arches), and the
/// side mirrors on the front doors (their faces against the body left out:
/// they would lie in the door's plane).
fn wheels_and_mirrors(m: &mut Mesh, l: &Layout) {
    let [radius, rim_radius, half_width] = l.proportions.wheel;
    let size =
        WheelSize { radius: radius as f32, rim_radius: rim_radius as f32, half_width: half_width as f32 };
    let hw = l.half_width;
    let bh = l.dims.bonnet_height_m;
    for (side, s) in SIDES {
        for (axle, x) in ["front", "rear"].into_iter().zip(l.axles) {
            let (tyre, rim) = (format!("tyre_{axle}_{side}"), format!("rim_{axle}_{side}"));
            let centre = v(x, (hw - 0.02 - half_width) * s, radius);
            wheel(m, centre, s as f32, [&tyre, &rim], size);
        }
        let x0 = l.windshield_base;
        let (y0, y1) = ordered(hw * s, (hw + 0.2) * s);
        let against_body = if s > 0.0 { MINUS_Y } else { PLUS_Y };
        trim(
            m,
            v(x0 - 0.35, y0, bh - 0.05),
            v(x0 - 0.15, y1, bh + 0.15),
            &format!("side_mirror_{side}"),
            against_body,
        );
    }
}
