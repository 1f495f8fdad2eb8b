//! The built-in demo: a procedural pickup truck, a four-way intersection with
//! corner buildings, and the paper's scenarios A–D.
//!
//! The truck is about a 2015 F-150 (5.9 m long, 2.0 m wide without mirrors,
//! 1.9 m high) built from boxes, a cab profile and wheels, with named exterior
//! parts in the spirit of the paper's 68. The intersection is centred at the
//! origin (+X east, +Y north), with 8 m wide streets, 3 m sidewalks and a
//! block of buildings on every corner; the pedestrian stands at the
//! south-west corner at the crosswalks. In every scenario the truck turns
//! right out of a cross street hidden behind a corner building (0–1.3 s),
//! drives straight (1.3–2.3 s) and brakes to a stop at the crosswalk
//! (2.3–3.0 s); B, C and D are A rotated by 180°, 270° and 90° about the
//! intersection, so the truck arrives from the west (A), east (B), north (C)
//! or south (D).

use glam::{DMat4, DVec2, Vec3, dvec2, dvec3, vec3};

use crate::scene::mesh::Mesh;
use crate::scene::moving::{FollowOffset, MovingOccluder, OccluderPath};
use crate::scene::occluders::Occluders;
use crate::scene::rig::Rig;
use crate::scene::scenario::Scenario;
use crate::scene::shapes::{TRUCK_WHEEL, wheel};
use crate::scene::track::{Key, Motion, Track, ValueOrTrack};

/// Truck dimensions: length, width (body), height.
pub(crate) const TRUCK_SIZE: [f64; 3] = [5.9, 2.0, 1.9];

/// Where the pedestrian stands (south-west corner).
pub(crate) const PEDESTRIAN: [f64; 3] = [-5.5, -5.5, 0.0];

/// The procedural pickup truck in its own frame (x forward, y left, z up).
#[allow(clippy::too_many_lines)] // data as code: the truck's boxes, one line each
pub(crate) fn truck() -> Mesh {
    let mut m = Mesh::default();
    let v = vec3;
    let hl = 2.95_f32; // half length
    let hw = 1.0_f32; // half width
    // Per side: (suffix, sign of y).
    let sides = [("left", 1.0_f32), ("right", -1.0_f32)];

    // Engine bay: hood on top, front fenders on the sides, grille panel in front.
    m.add_box(
        v(1.6, -hw, 0.45),
        v(2.75, hw, 1.15),
        [Some("grill"), None, Some("front_fender_left"), Some("front_fender_right"), Some("hood"), None],
    );
    // Grille insert and headlights stand proud of the front panel.
    m.add_box(
        v(2.75, -0.55, 0.62),
        v(2.8, 0.55, 1.08),
        [Some("grill"), None, Some("grill"), Some("grill"), Some("grill"), Some("grill")],
    );
    for (side, s) in sides {
        let (y0, y1) = if s > 0.0 { (0.6, 0.95) } else { (-0.95, -0.6) };
        let name = format!("headlight_{side}");
        m.add_box(
            v(2.75, y0, 0.78),
            v(2.8, y1, 1.06),
            [Some(&name), None, Some(&name), Some(&name), Some(&name), Some(&name)],
        );
    }
    // Front bumper and plate.
    let bumper = Some("front_bumper");
    m.add_box(v(2.75, -hw, 0.28), v(hl, hw, 0.58), [bumper, None, bumper, bumper, bumper, bumper]);
    m.add_box(
        v(hl, -0.3, 0.33),
        v(hl + 0.02, 0.3, 0.5),
        [
            Some("front_license_plate"),
            None,
            Some("front_license_plate"),
            Some("front_license_plate"),
            Some("front_license_plate"),
            Some("front_license_plate"),
        ],
    );

    // Cab lower body: doors (front x 0.5..1.6, rear -0.6..0.5).
    for (door, x0, x1) in [("front", 0.5, 1.6), ("rear", -0.6, 0.5)] {
        let l = format!("door_{door}_left");
        let r = format!("door_{door}_right");
        m.add_box(v(x0, -hw, 0.45), v(x1, hw, 1.2), [None, None, Some(&l), Some(&r), None, None]);
    }
    // Cab back wall below the rear window.
    m.add_quad("cab_back", v(-0.6, hw, 0.45), v(-0.6, -hw, 0.45), v(-0.6, -hw, 1.2), v(-0.6, hw, 1.2));
    // Belt line shelf between the door tops and the narrower greenhouse.
    m.add_quad("cab_shoulder", v(-0.6, -hw, 1.2), v(1.6, -hw, 1.2), v(1.6, hw, 1.2), v(-0.6, hw, 1.2));

    // Greenhouse: side profile (x, z) extruded across y = ±0.95.
    let gw = 0.95_f32;
    let rail = 0.08_f32;
    let (wx0, wz0, wx1, wz1) = (1.6_f32, 1.2_f32, 0.95_f32, 1.9_f32); // windshield base and top
    // Windshield with rails (A-pillars) along its sides.
    for (name, y0, y1) in [
        ("windshield_rail_right", -gw, -gw + rail),
        ("windshield", -gw + rail, gw - rail),
        ("windshield_rail_left", gw - rail, gw),
    ] {
        m.add_quad(name, v(wx0, y0, wz0), v(wx0, y1, wz0), v(wx1, y1, wz1), v(wx1, y0, wz1));
    }
    m.add_quad("roof", v(wx1, -gw, wz1), v(wx1, gw, wz1), v(-0.6, gw, wz1), v(-0.6, -gw, wz1));
    m.add_quad("rear_window", v(-0.6, gw, 1.2), v(-0.6, -gw, 1.2), v(-0.6, -gw, wz1), v(-0.6, gw, wz1));
    for (side, s) in sides {
        let y = gw * s;
        let front = format!("window_front_{side}");
        let rear = format!("window_rear_{side}");
        let pillar = format!("b_pillar_{side}");
        // Quads listed counter-clockwise seen from that side.
        let quad = |m: &mut Mesh, name: &str, a: Vec3, b: Vec3, c: Vec3, d: Vec3| {
            if s > 0.0 { m.add_quad(name, a, b, c, d) } else { m.add_quad(name, b, a, d, c) }
        };
        quad(&mut m, &front, v(0.55, y, 1.2), v(wx0, y, wz0), v(wx1, y, wz1), v(0.55, y, wz1));
        quad(&mut m, &pillar, v(0.45, y, 1.2), v(0.55, y, 1.2), v(0.55, y, wz1), v(0.45, y, wz1));
        quad(&mut m, &rear, v(-0.6, y, 1.2), v(0.45, y, 1.2), v(0.45, y, wz1), v(-0.6, y, wz1));
    }

    // Bed: side walls with rear fenders over the wheels, floor, tailgate.
    for (side, s) in sides {
        let (y0, y1) = if s > 0.0 { (0.88, hw) } else { (-hw, -0.88) };
        let outer = format!("bed_side_{side}");
        let fender = format!("rear_fender_{side}");
        let (pos, neg) = if s > 0.0 {
            (Some(outer.as_str()), Some("truck_bed"))
        } else {
            (Some("truck_bed"), Some(outer.as_str()))
        };
        m.add_box(v(-2.8, y0, 0.45), v(-0.65, y1, 1.25), [None, None, pos, neg, Some("bed_rail"), None]);
        let (f0, f1) = if s > 0.0 { (hw, hw + 0.05) } else { (-hw - 0.05, -hw) };
        let (fp, fn_) = if s > 0.0 { (Some(fender.as_str()), None) } else { (None, Some(fender.as_str())) };
        // A flare over the wheel arch, its underside open to view.
        m.add_box(
            v(-2.4, f0, 0.86),
            v(-1.3, f1, 1.0),
            [Some(&fender), Some(&fender), fp, fn_, Some(&fender), Some(&fender)],
        );
        let tail = format!("tail_light_{side}");
        let (t0, t1) = if s > 0.0 { (0.78, 0.98) } else { (-0.98, -0.78) };
        m.add_box(
            v(-2.87, t0, 0.8),
            v(-2.8, t1, 1.2),
            [None, Some(&tail), Some(&tail), Some(&tail), Some(&tail), Some(&tail)],
        );
        // Side mirrors on the doors, step bars below them; the faces against
        // the body are left out (they would lie in the door's plane and fight it).
        let outward = |name: &str| -> [Option<String>; 6] {
            let n = || Some(name.to_string());
            if s > 0.0 { [n(), n(), n(), None, n(), n()] } else { [n(), n(), None, n(), n(), n()] }
        };
        let mirror = outward(&format!("side_mirror_{side}"));
        let (m0, m1) = if s > 0.0 { (hw, hw + 0.24) } else { (-hw - 0.24, -hw) };
        m.add_box(v(1.3, m0, 1.12), v(1.5, m1, 1.36), mirror.each_ref().map(|f| f.as_deref()));
        let step = outward(&format!("step_bar_{side}"));
        let (s0, s1) = if s > 0.0 { (hw, hw + 0.12) } else { (-hw - 0.12, -hw) };
        m.add_box(v(-0.6, s0, 0.3), v(1.5, s1, 0.38), step.each_ref().map(|f| f.as_deref()));
    }
    m.add_quad(
        "truck_bed",
        v(-2.8, -0.88, 0.6),
        v(-0.65, -0.88, 0.6),
        v(-0.65, 0.88, 0.6),
        v(-2.8, 0.88, 0.6),
    );
    m.add_quad(
        "truck_bed",
        v(-0.65, -0.88, 0.6),
        v(-0.65, 0.88, 0.6),
        v(-0.65, 0.88, 1.25),
        v(-0.65, -0.88, 1.25),
    );
    m.add_box(
        v(-2.85, -0.88, 0.45),
        v(-2.7, 0.88, 1.25),
        [Some("truck_bed"), Some("tailgate"), None, None, Some("tailgate"), None],
    );
    m.add_box(
        v(-2.87, -0.3, 0.55),
        v(-2.85, 0.3, 0.7),
        [
            None,
            Some("rear_license_plate"),
            Some("rear_license_plate"),
            Some("rear_license_plate"),
            Some("rear_license_plate"),
            Some("rear_license_plate"),
        ],
    );
    m.add_box(
        v(-hl, -hw, 0.28),
        v(-2.8, hw, 0.45),
        [
            None,
            Some("rear_bumper"),
            Some("rear_bumper"),
            Some("rear_bumper"),
            Some("rear_bumper"),
            Some("rear_bumper"),
        ],
    );

    // Wheels: tyre tread and sidewall, rim disc on the outer face. The tyres
    // stand 2 cm proud of the body so that no sidewall lies in a body panel's plane.
    for (axle, x) in [("front", 1.85_f32), ("rear", -1.85_f32)] {
        for (side, s) in sides {
            let (tyre, rim) = (format!("tyre_{axle}_{side}"), format!("rim_{axle}_{side}"));
            wheel(&mut m, vec3(x, 0.88 * s, 0.42), s, [&tyre, &rim], TRUCK_WHEEL);
        }
    }
    m
}

/// The intersection's occluders: ground, and the corner buildings.
pub(crate) fn intersection() -> Occluders {
    let mut occluders = Occluders::default();
    // The ground hides the underside of the truck (it would never be seen).
    let mut ground = Mesh::default();
    let g = 200.0_f32;
    ground.add_quad("ground", vec3(-g, -g, 0.0), vec3(g, -g, 0.0), vec3(g, g, 0.0), vec3(-g, g, 0.0));
    occluders.begin_named("ground");
    occluders.add_mesh(&ground, DMat4::IDENTITY);
    // Blocks between the main streets (|x|, |y| < 4 m, sidewalks to 7 m) and the
    // cross streets 31.35 m out, and beyond those; heights vary per block.
    let spans: [(f64, f64); 2] = [(7.5, 27.0), (35.5, 60.0)];
    let mut number = 0;
    for sx in [-1.0_f64, 1.0] {
        for sy in [-1.0_f64, 1.0] {
            for (x0, x1) in spans {
                for (y0, y1) in spans {
                    let height = 10.0 + f64::from(number % 4) * 4.0;
                    number += 1;
                    occluders.begin_named(format!("building {number}"));
                    let (ax, bx) = (sx * x0, sx * x1);
                    let (ay, by) = (sy * y0, sy * y1);
                    occluders
                        .add_box(dvec3(ax.min(bx), ay.min(by), 0.0), dvec3(ax.max(bx), ay.max(by), height));
                }
            }
        }
    }
    occluders
}

/// The demo rig: the paper's defaults with the pedestrian at the south-west
/// corner, looking at the middle of the truck.
pub(crate) fn rig() -> Rig {
    Rig { pedestrian: ValueOrTrack::Fixed(PEDESTRIAN), look_at_vehicle: [0.0, 0.0, 0.95], ..Rig::default() }
}

/// Scenario names and their rotation about the intersection (degrees).
pub(crate) const SCENARIOS: [(&str, f64, &str); 4] = [
    ("A", 0.0, "from the west"),
    ("B", 180.0, "from the east"),
    ("C", 270.0, "from the north"),
    ("D", 90.0, "from the south"),
];

/// The demo scenario `name` (A–D).
pub(crate) fn scenario(name: &str) -> Option<Scenario> {
    scenario_for_length(name, TRUCK_SIZE[0])
}

/// The demo scenario `name` (A–D) for a vehicle `length_m` long: the same
/// path, shifted so that its front bumper stops at the stop line.
pub(crate) fn scenario_for_length(name: &str, length_m: f64) -> Option<Scenario> {
    let &(name, rotation, _) = SCENARIOS.iter().find(|(n, _, _)| n.eq_ignore_ascii_case(name))?;
    // Scenario A: north up the cross street at x = -29.35, right turn into
    // the eastbound lane (y = -2), straight at 8 m/s, then braking at a
    // constant 11.4 m/s² to stop with the front bumper at the stop line
    // (x = -9), half the vehicle's length (2.95 m for the truck) ahead of its centre.
    let stop = -9.0 - length_m / 2.0;
    let brake_start = stop - 2.8;
    let straight_start = brake_start - 8.0;
    let keys: [(f64, DVec2, DVec2, f64); 4] = [
        (0.0, dvec2(-29.35, -14.0), dvec2(0.0, 12.0), 90.0),
        (1.3, dvec2(straight_start, -2.0), dvec2(8.0, 0.0), 0.0),
        (2.3, dvec2(brake_start, -2.0), dvec2(8.0, 0.0), 0.0),
        (3.0, dvec2(stop, -2.0), dvec2(0.0, 0.0), 0.0),
    ];
    let rotate = |p: DVec2| DVec2::from_angle(rotation.to_radians()).rotate(p);
    let position = keys
        .iter()
        .map(|&(t, p, slope, _)| {
            let p = rotate(p);
            let slope = rotate(slope);
            Key::smooth(t, [p.x, p.y, 0.0], [slope.x, slope.y, 0.0])
        })
        .collect();
    let yaw = keys.iter().map(|&(t, _, _, yaw)| Key::smooth(t, [yaw + rotation], [0.0])).collect();
    let motion = Motion { position: Track { keys: position }, yaw_deg: Track { keys: yaw } };
    Some(Scenario { name: name.to_string(), duration_s: 3.0, motion })
}

/// Traffic for the demo (`ufcsr capture demo --traffic`): a second pickup,
/// the truck's twin, driving with the truck.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DemoTraffic {
    /// Beside the truck, [`ADJACENT_LANE_M`] to the side of the pedestrian
    /// and [`ADJACENT_LANE_AHEAD_M`] ahead (the multiple-threat crossing:
    /// it stops nearer the crosswalk): to its right in A and C,
    /// where the pedestrian waits at the near kerb (the twin then runs
    /// along the kerb: the demo's streets have one lane each way), to its
    /// left in B and D, where the pedestrian is across the street (the twin
    /// runs in the oncoming lane).
    AdjacentLane,
    /// [`LEAD_CAR_AHEAD_M`] ahead of the truck in its lane.
    LeadCar,
}

/// How far the adjacent-lane twin drives to the side of the truck, centre
/// to centre, metres: about a lane.
pub const ADJACENT_LANE_M: f64 = 3.5;
/// How far ahead of the truck the adjacent-lane twin drives, centre to
/// centre, metres: it stops 2 m nearer the crosswalk.
pub const ADJACENT_LANE_AHEAD_M: f64 = 2.0;
/// How far ahead the lead car drives, centre to centre, metres (a 3.1 m gap
/// between the two 5.9 m pickups).
pub const LEAD_CAR_AHEAD_M: f64 = 9.0;

impl DemoTraffic {
    /// The name of the moving occluder (in the manifest and `scene.glb`).
    pub fn name(self) -> &'static str {
        match self {
            DemoTraffic::AdjacentLane => "adjacent-lane pickup",
            DemoTraffic::LeadCar => "lead pickup",
        }
    }

    /// The twin's offset from the truck in `scenario`: for the adjacent
    /// lane, to the side the pedestrian is on when the truck stops.
    pub fn offset(self, scenario: &Scenario) -> FollowOffset {
        match self {
            DemoTraffic::LeadCar => FollowOffset { ahead_m: LEAD_CAR_AHEAD_M, ..FollowOffset::default() },
            DemoTraffic::AdjacentLane => {
                let end = scenario.motion.pose(scenario.duration_s);
                let to_pedestrian = (glam::DVec3::from(PEDESTRIAN) - end.position).truncate();
                let left = DVec2::from_angle(end.yaw_deg.to_radians()).perp();
                let side = if to_pedestrian.dot(left) >= 0.0 { 1.0 } else { -1.0 };
                FollowOffset {
                    ahead_m: ADJACENT_LANE_AHEAD_M,
                    left_m: side * ADJACENT_LANE_M,
                    ..FollowOffset::default()
                }
            }
        }
    }

    /// The twin as a moving occluder in `scenario`.
    pub fn occluder(self, scenario: &Scenario) -> MovingOccluder {
        MovingOccluder {
            name: self.name().into(),
            mesh: truck(),
            path: OccluderPath::Follow(self.offset(scenario)),
        }
    }
}

/// Bounds of the truck in its frame.
#[cfg(test)]
pub(crate) fn truck_bounds() -> (glam::DVec3, glam::DVec3) {
    truck().bounds()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::rig::{box_corners, vehicle_to_world};
    use glam::DVec3;

    #[test]
    fn truck_has_f150_size_and_named_parts() {
        let truck = truck();
        let (min, max) = truck.bounds();
        let size = max - min;
        assert!((size.x - 5.9).abs() < 0.05, "{size}");
        // Body 2.0 m wide; mirrors stick out beyond it.
        assert!((2.0..2.6).contains(&size.y), "{size}");
        assert!((size.z - 1.9).abs() < 0.05, "{size}");
        for part in [
            "front_bumper",
            "grill",
            "hood",
            "windshield",
            "windshield_rail_left",
            "roof",
            "door_front_left",
            "door_rear_right",
            "window_front_left",
            "window_rear_right",
            "front_fender_left",
            "rear_fender_right",
            "tyre_front_left",
            "rim_rear_right",
            "side_mirror_left",
            "headlight_right",
            "tail_light_left",
            "tailgate",
            "truck_bed",
            "step_bar_left",
            "front_license_plate",
            "rear_license_plate",
            "rear_bumper",
        ] {
            assert!(truck.parts.iter().any(|p| p == part), "missing {part}");
        }
        assert!(truck.parts.len() >= 40, "{}", truck.parts.len());
    }

    /// Two triangles in one plane that overlap would fight in the depth
    /// buffer, and which one a pixel shows would depend on the driver.
    #[test]
    fn truck_has_no_overlapping_coplanar_triangles() {
        let overlaps = crate::scene::shapes::coplanar_overlaps(&truck());
        assert!(
            overlaps.is_empty(),
            "{} coplanar overlaps, e.g. {:?}",
            overlaps.len(),
            &overlaps[..overlaps.len().min(5)]
        );
    }

    #[test]
    fn the_adjacent_lane_twin_drives_on_the_pedestrians_side_and_the_lead_car_ahead() {
        for (name, _, _) in SCENARIOS {
            let scenario = scenario(name).unwrap();
            let end = scenario.motion.pose(scenario.duration_s);
            let twin = DemoTraffic::AdjacentLane.occluder(&scenario).pose(3.0, &end);
            let pedestrian = dvec2(PEDESTRIAN[0], PEDESTRIAN[1]);
            let gap = |p: glam::DVec3| (p.truncate() - pedestrian).length();
            assert!(gap(twin.position) < gap(end.position), "{name}: the twin is on the far side");
            let beside = (ADJACENT_LANE_M.powi(2) + ADJACENT_LANE_AHEAD_M.powi(2)).sqrt();
            assert!(((twin.position - end.position).length() - beside).abs() < 1e-9);
            let lead = DemoTraffic::LeadCar.occluder(&scenario).pose(3.0, &end);
            let ahead = lead.position - end.position;
            let heading = DVec2::from_angle(end.yaw_deg.to_radians());
            assert!((ahead.truncate().dot(heading) - LEAD_CAR_AHEAD_M).abs() < 1e-9, "{name}: {ahead}");
        }
    }

    #[test]
    fn scenarios_stop_at_the_crosswalk_and_start_hidden() {
        let occluders = intersection();
        for (name, _, _) in SCENARIOS {
            let scenario = scenario(name).unwrap();
            scenario.motion.check().unwrap();
            let end = scenario.motion.pose(3.0);
            let distance = (end.position.truncate() - dvec2(PEDESTRIAN[0], PEDESTRIAN[1])).length();
            assert!(distance < 25.0, "{name}: {distance}");
            // At t = 0 the truck's box is behind a building as seen from the
            // eyes: check the sight lines to its corners cross a block.
            let pose = scenario.motion.pose(0.0);
            let (min, max) = truck_bounds();
            let eye = dvec3(PEDESTRIAN[0], PEDESTRIAN[1], 1.75);
            for corner in box_corners(min, max) {
                let p = vehicle_to_world(&pose).transform_point3(corner);
                let blocked =
                    occluders.objects.iter().skip(1).any(|o| segment_hits_box(eye, p, o.min, o.max));
                assert!(blocked, "{name}: corner {p} visible at t=0");
            }
        }
    }

    fn segment_hits_box(a: DVec3, b: DVec3, lo: DVec3, hi: DVec3) -> bool {
        let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
        let d = b - a;
        for axis in 0..3 {
            if d[axis].abs() < 1e-12 {
                if a[axis] < lo[axis] || a[axis] > hi[axis] {
                    return false;
                }
                continue;
            }
            let (mut u, mut v) = ((lo[axis] - a[axis]) / d[axis], (hi[axis] - a[axis]) / d[axis]);
            if u > v {
                std::mem::swap(&mut u, &mut v);
            }
            t0 = t0.max(u);
            t1 = t1.min(v);
        }
        t0 <= t1
    }
}
