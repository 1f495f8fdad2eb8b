//! The street design of the raycasting study (arXiv 2507.08973), as a scene
//! generator (issue 36 item 3): a two-way two-lane street with walkways on
//! both sides and two alleyways, eight vehicle positions (three per lane,
//! one per alleyway with the vehicle's nose over the sidewalk), static or
//! approaching its position along its heading at a stated speed, up to seven
//! other vehicles of the same model on the other positions (chosen by a
//! seeded generator), and the pedestrian at one of three places on the near
//! sidewalk, looking at the vehicle.
//!
//! The paper's text could not be read here, so every number below is OURS
//! unless `docs/design.md` says otherwise (it lists each with its status);
//! the layout is what the summary of the paper says: positions, lanes,
//! walkways, alleyways, up to 7 others, pedestrians on the sidewalk.
//! World: +X along the street (the near lane drives +X), +Y across it
//! (near sidewalk at −Y), z up; the street is centred on the origin.

use glam::{DMat4, DVec3, dvec3};

use crate::error::{CaptureError, Result};
use crate::scene::mesh::Mesh;
use crate::scene::occluders::Occluders;
use crate::scene::rig::{Rig, vehicle_to_world};
use crate::scene::scenario::Scenario;
use crate::scene::track::{Key, Motion, Pose, Track, ValueOrTrack};

/// Lane width, metres (ours: a common urban lane).
pub(crate) const LANE_WIDTH_M: f64 = 3.5;
/// Walkway (sidewalk) width, metres (ours).
pub(crate) const WALKWAY_WIDTH_M: f64 = 2.5;
/// Kerb height, metres (ours).
pub(crate) const KERB_HEIGHT_M: f64 = 0.15;
/// Alleyway width, metres (ours).
pub(crate) const ALLEY_WIDTH_M: f64 = 4.0;
/// Where the two alleyways cross the walkways: near side at +X, far side at −X, metres (ours).
pub(crate) const ALLEY_X_M: f64 = 10.0;
/// Height of the building blocks lining the street, metres (ours).
pub(crate) const BUILDING_HEIGHT_M: f64 = 10.0;
/// Half the length of the street modelled, metres (ours).
pub(crate) const STREET_HALF_LENGTH_M: f64 = 60.0;
/// The lane positions' vehicle centres along X: near lane (driving +X)
/// positions 1–3, far lane (driving −X) 4–6, metres (ours).
pub(crate) const LANE_POSITIONS_X_M: [[f64; 3]; 2] = [[-20.0, -12.0, -5.0], [20.0, 12.0, 5.0]];
/// The pedestrian's places 1–3 on the near walkway, X metres (ours).
pub(crate) const PEDESTRIAN_X_M: [f64; 3] = [0.0, -6.0, 6.0];
/// How far from the kerb the pedestrian stands, metres (ours).
pub(crate) const PEDESTRIAN_FROM_KERB_M: f64 = 0.5;
/// Seconds a static position is recorded (ours; longer than the placement
/// rules' 1 s dwell, so a legible display can count).
pub(crate) const STATIC_SECONDS: f64 = 2.0;
/// Seconds an approach lasts, ending at the position (ours).
pub(crate) const APPROACH_SECONDS: f64 = 3.0;
/// Largest recorded pedestrian–vehicle distance: an approach starts no
/// farther than this (ours).
pub(crate) const MAX_RECORDED_DISTANCE_M: f64 = 50.0;
/// Smallest recorded distance: a position nearer the pedestrian is refused (ours).
pub(crate) const MIN_RECORDED_DISTANCE_M: f64 = 2.0;
/// Other vehicles at most (the paper's "up to 7").
pub(crate) const MAX_OTHER_VEHICLES: u32 = 7;
/// Vehicle positions (the paper's 8).
pub(crate) const POSITIONS: u32 = 8;

/// One street scenario.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StreetOptions {
    /// 1–8.
    pub position: u32,
    /// 1–3.
    pub pedestrian: u32,
    /// 0: static; more: approaching at this speed, m/s.
    pub speed_mps: f64,
    /// Other vehicles of the same model, 0–7.
    pub others: u32,
    /// Seed of the other vehicles' positions.
    pub seed: u64,
}

/// The pose of a vehicle `length_m` long standing at `position` (1–8).
pub(crate) fn position_pose(position: u32, length_m: f64) -> Result<Pose> {
    let half = LANE_WIDTH_M / 2.0;
    let (x, y, yaw) = match position {
        1..=3 => (LANE_POSITIONS_X_M[0][position as usize - 1], -half, 0.0),
        4..=6 => (LANE_POSITIONS_X_M[1][position as usize - 4], half, 180.0),
        // Out of the near alley, heading +Y, nose at the kerb line.
        7 => (ALLEY_X_M, -LANE_WIDTH_M - length_m / 2.0 + 0.5, 90.0),
        8 => (-ALLEY_X_M, LANE_WIDTH_M + length_m / 2.0 - 0.5, -90.0),
        _ => {
            return Err(CaptureError::BadOptions(format!(
                "street position {position}: must be 1 to {POSITIONS}"
            )));
        }
    };
    Ok(Pose { position: dvec3(x, y, 0.0), yaw_deg: yaw })
}

/// Where the pedestrian stands (1–3).
pub(crate) fn pedestrian_at(place: u32) -> Result<[f64; 3]> {
    let x = *PEDESTRIAN_X_M
        .get((place as usize).wrapping_sub(1))
        .ok_or_else(|| CaptureError::BadOptions(format!("street pedestrian {place}: must be 1 to 3")))?;
    // On the walkway, whose top is the kerb's height.
    Ok([x, -LANE_WIDTH_M - PEDESTRIAN_FROM_KERB_M, KERB_HEIGHT_M])
}

/// The scenario: standing at the position, or approaching it.
fn street_scenario(options: &StreetOptions, end: Pose, pedestrian: DVec3) -> Result<Scenario> {
    let distance = (end.position - pedestrian).truncate().length();
    if distance < MIN_RECORDED_DISTANCE_M {
        return Err(CaptureError::BadOptions(format!(
            "street position {}: {distance:.2} m from the pedestrian, nearer than {MIN_RECORDED_DISTANCE_M} m",
            options.position
        )));
    }
    let name = format!("street-p{}-ped{}", options.position, options.pedestrian);
    let p = end.position.to_array();
    if !(options.speed_mps.is_finite() && (0.0..=40.0).contains(&options.speed_mps)) {
        return Err(CaptureError::BadOptions(format!(
            "street speed {} m/s: must be 0 to 40",
            options.speed_mps
        )));
    }
    if options.speed_mps == 0.0 {
        let motion = Motion {
            position: Track::new(vec![Key::linear(0.0, p)])?,
            yaw_deg: Track::new(vec![Key::linear(0.0, [end.yaw_deg])])?,
        };
        return Ok(Scenario { name, duration_s: STATIC_SECONDS, motion });
    }
    let heading = dvec3(end.yaw_deg.to_radians().cos(), end.yaw_deg.to_radians().sin(), 0.0);
    // Back along the heading, no farther from the pedestrian than the maximum.
    let mut back = options.speed_mps * APPROACH_SECONDS;
    while back > 0.0 && (end.position - heading * back - pedestrian).length() > MAX_RECORDED_DISTANCE_M {
        back -= 0.5;
    }
    let duration = (back / options.speed_mps).max(STATIC_SECONDS);
    let start = (end.position - heading * back).to_array();
    let motion = Motion {
        position: Track::new(vec![Key::linear(0.0, start), Key::linear(duration, p)])?,
        yaw_deg: Track::new(vec![Key::linear(0.0, [end.yaw_deg])])?,
    };
    Ok(Scenario { name, duration_s: duration, motion })
}

/// The other vehicles' positions: `others` of the seven not taken, drawn
/// without replacement; an approaching vehicle's own lane is left free.
pub(crate) fn other_positions(options: &StreetOptions) -> Result<Vec<u32>> {
    if options.others > MAX_OTHER_VEHICLES {
        return Err(CaptureError::BadOptions(format!(
            "{} other vehicles: the street design holds at most {MAX_OTHER_VEHICLES}",
            options.others
        )));
    }
    let lane = |p: u32| (p - 1) / 3;
    let mut free: Vec<u32> = (1..=POSITIONS)
        .filter(|&p| p != options.position)
        .filter(|&p| options.speed_mps == 0.0 || options.position > 6 || lane(p) != lane(options.position))
        .collect();
    if options.others as usize > free.len() {
        return Err(CaptureError::BadOptions(format!(
            "{} other vehicles: an approaching vehicle leaves its lane free, {} positions remain",
            options.others,
            free.len()
        )));
    }
    // Seeded: the other vehicles' positions must not change between runs.
    let mut random = ufcsr::SplitMix64(options.seed);
    let mut chosen = Vec::new();
    for _ in 0..options.others {
        let i = random.below(free.len() as u64) as usize;
        chosen.push(free.remove(i));
    }
    chosen.sort_unstable();
    Ok(chosen)
}

/// The street: ground, kerbs and walkways, building blocks with the alleys' gaps.
pub(crate) fn street_occluders() -> Occluders {
    let mut occluders = Occluders::default();
    let l = STREET_HALF_LENGTH_M;
    let (lane, walk) = (LANE_WIDTH_M, WALKWAY_WIDTH_M);
    occluders.begin_named("ground");
    occluders.add_box(dvec3(-l, -l, -0.1), dvec3(l, l, 0.0));
    occluders.begin_named("walkways");
    occluders.add_box(dvec3(-l, -lane - walk, 0.0), dvec3(l, -lane, KERB_HEIGHT_M));
    occluders.add_box(dvec3(-l, lane, 0.0), dvec3(l, lane + walk, KERB_HEIGHT_M));
    occluders.begin_named("buildings");
    let (y0, y1) = (lane + walk, lane + walk + 12.0);
    let half_alley = ALLEY_WIDTH_M / 2.0;
    // Near side: gap at +ALLEY_X; far side: gap at −ALLEY_X.
    for (side, gap) in [(-1.0, ALLEY_X_M), (1.0, -ALLEY_X_M)] {
        let (ya, yb) = if side < 0.0 { (-y1, -y0) } else { (y0, y1) };
        occluders.add_box(dvec3(-l, ya, 0.0), dvec3(gap - half_alley, yb, BUILDING_HEIGHT_M));
        occluders.add_box(dvec3(gap + half_alley, ya, 0.0), dvec3(l, yb, BUILDING_HEIGHT_M));
    }
    occluders
}

/// The scene parts the street generator makes for `vehicle`: the
/// occluders (street and other vehicles), the rig and the scenario.
pub fn street_scene(vehicle: &Mesh, options: &StreetOptions) -> Result<(Occluders, Rig, Scenario)> {
    let (min, max) = vehicle.bounds();
    let length = max.x - min.x;
    let end = position_pose(options.position, length)?;
    let pedestrian = pedestrian_at(options.pedestrian)?;
    let scenario = street_scenario(options, end, DVec3::from(pedestrian))?;
    let mut occluders = street_occluders();
    for other in other_positions(options)? {
        occluders.begin_named(format!("other vehicle at position {other}"));
        let pose = position_pose(other, length)?;
        occluders.add_mesh(vehicle, vehicle_to_world(&pose) * DMat4::IDENTITY);
    }
    let rig = Rig {
        pedestrian: ValueOrTrack::Fixed(pedestrian),
        look_at_vehicle: [0.0, 0.0, (max.z + min.z) / 2.0],
        ..Rig::default()
    };
    Ok((occluders, rig, scenario))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn options(position: u32, speed: f64, others: u32) -> StreetOptions {
        StreetOptions { position, pedestrian: 1, speed_mps: speed, others, seed: 3 }
    }

    #[test]
    fn the_eight_positions_are_three_per_lane_and_one_per_alley_over_the_walkway() {
        for p in 1..=8 {
            let pose = position_pose(p, 5.0).unwrap();
            let y = pose.position.y;
            match p {
                1..=3 => assert!(y < 0.0 && y > -LANE_WIDTH_M && pose.yaw_deg == 0.0),
                4..=6 => assert!(y > 0.0 && y < LANE_WIDTH_M && pose.yaw_deg == 180.0),
                // The nose (centre + half length along the heading) is over the carriageway edge,
                // the body over the walkway.
                _ => assert!(y.abs() > LANE_WIDTH_M && y.abs() - 2.5 < LANE_WIDTH_M),
            }
        }
        assert!(position_pose(0, 5.0).is_err() && position_pose(9, 5.0).is_err());
    }

    #[test]
    fn other_vehicles_are_distinct_seeded_and_leave_an_approach_lane_free() {
        let a = other_positions(&options(2, 0.0, 7)).unwrap();
        assert_eq!(a, vec![1, 3, 4, 5, 6, 7, 8]);
        let b = other_positions(&options(2, 10.0, 5)).unwrap();
        assert!(b.iter().all(|&p| p > 3), "{b:?}");
        assert_eq!(b, other_positions(&options(2, 10.0, 5)).unwrap());
        assert!(other_positions(&options(2, 10.0, 6)).is_err());
        assert!(other_positions(&options(2, 0.0, 8)).unwrap_err().to_string().contains("at most 7"));
    }

    #[test]
    fn an_approach_ends_at_the_position_and_starts_within_the_largest_distance() {
        let vehicle = crate::scene::demo::truck();
        let (_, rig, scenario) = street_scene(&vehicle, &options(1, 15.0, 2)).unwrap();
        let end = scenario.motion.pose(scenario.duration_s).position;
        assert!((end - position_pose(1, 5.9).unwrap().position).length() < 0.1);
        let start = scenario.motion.pose(0.0).position;
        let pedestrian = DVec3::from(rig.pedestrian.eval(0.0));
        assert!((start - pedestrian).length() <= MAX_RECORDED_DISTANCE_M + 1e-9);
        assert!(start.x < end.x, "the near lane drives +X");
    }
}
