//! From a body's seven dimensions to the positions of its breaks: where the
//! front face, the windshield, the B-pillar, the doors, the cab and the rear
//! are along x, how high the bumper, the arches and the bed floor are. The
//! few proportions the dimensions do not give (wheel size, ground clearance,
//! door lengths, the sedan's boot and backlight, trim depths) are ours, per
//! body type, and listed in `docs/vehicles.md`.
//!
//! Every check that could make a panel degenerate, inside out or lying on
//! another is made here, before a triangle is built, and names the field to
//! change: the builder can then trust the order of the breaks.

use crate::scene::family::{BodyDims, BodyType};

/// How far the licence plate stands proud of the bumper, and the bumper of
/// the front and rear faces, metres.
pub(crate) const PLATE_DEPTH_M: f64 = 0.015;
/// The bumper's depth in front of the grill panel (and behind the rear face).
pub(crate) const BUMPER_DEPTH_M: f64 = 0.045;
/// How far the greenhouse (windows and roof) is set in from the body sides.
pub(crate) const GREENHOUSE_INSET_M: f64 = 0.05;
/// Clearance between a tyre and its arch, metres (up and along x).
pub(crate) const ARCH_CLEARANCE_M: f64 = 0.05;

/// What the dimensions leave open, per body type (ours).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Proportions {
    /// Tyre radius, rim radius, half the tyre width.
    pub wheel: [f64; 3],
    /// Height of the body's lower edge (and the bumpers') above the ground.
    pub clearance_m: f64,
    /// Front door length at the belt, at most (the B-pillar may come sooner).
    pub front_door_m: f64,
    /// Rear (or sliding) door length; the pickup's rear door ends at its cab.
    pub rear_door_m: f64,
}

impl Proportions {
    pub(crate) fn of(body: BodyType) -> Proportions {
        let p = |wheel, clearance_m, front_door_m, rear_door_m| Proportions {
            wheel,
            clearance_m,
            front_door_m,
            rear_door_m,
        };
        match body {
            // 205/65 R15-size tyres (0.63 m).
            BodyType::Sedan => p([0.32, 0.19, 0.1], 0.25, 1.1, 1.0),
            BodyType::Suv => p([0.36, 0.22, 0.11], 0.35, 1.1, 1.0),
            BodyType::Van => p([0.35, 0.21, 0.11], 0.3, 1.1, 1.2),
            // The demo truck's wheels.
            BodyType::Pickup => p([0.42, 0.27, 0.14], 0.45, 1.1, 1.05),
            // The Citaro's 275/70 R22.5 tyres (0.957 m).
            BodyType::Bus => p([0.478, 0.29, 0.14], 0.3, 1.1, 0.0),
        }
    }
}

/// The body's breaks, metres in the vehicle frame (x forward, y left, z up).
#[derive(Debug, Clone)]
pub(crate) struct Layout {
    pub body: BodyType,
    pub dims: BodyDims,
    pub proportions: Proportions,
    /// Half length and half width.
    pub half_length: f64,
    pub half_width: f64,
    /// The grill panel (front face) and the rear face, x.
    pub front_face: f64,
    pub rear_face: f64,
    /// The windshield's base (x, at the belt) and top (x, at the roof).
    pub windshield_base: f64,
    pub windshield_top: f64,
    /// The B-pillar's rear and front edges, x.
    pub pillar: [f64; 2],
    /// Where the rear door ends (x); the pickup's cab back.
    pub rear_door_end: f64,
    /// The greenhouse's rear at the belt and at the roof (x): the sedan's
    /// backlight slopes between them, other bodies stand upright.
    pub greenhouse_rear: [f64; 2],
    /// Front and rear axle, x.
    pub axles: [f64; 2],
    /// Height of the arches' ceilings.
    pub arch_top: f64,
    /// The pickup bed's floor, z.
    pub bed_floor: f64,
}

impl Layout {
    /// The layout of `body` with `dims`, or what is wrong with them (naming the field).
    pub(crate) fn new(body: BodyType, dims: &BodyDims) -> Result<Layout, String> {
        check_ranges(dims)?;
        let proportions = Proportions::of(body);
        let BodyDims {
            length_m,
            width_m,
            height_m,
            bonnet_length_m,
            bonnet_height_m,
            windshield_rake_deg,
            wheelbase_m,
        } = *dims;
        let half_length = length_m / 2.0;
        let front_face = half_length - PLATE_DEPTH_M - BUMPER_DEPTH_M;
        let rear_face = -front_face;
        let arch_top = check_wheels(body, dims, &proportions)?;
        let windshield_base = half_length - bonnet_length_m;
        if windshield_base <= rear_face + 1.0 {
            return Err(format!(
                "bonnet_length_m {bonnet_length_m} leaves no room for a cabin in length_m {length_m}"
            ));
        }
        let windshield_top =
            windshield_base - (height_m - bonnet_height_m) * windshield_rake_deg.to_radians().tan();
        let pillar_front = (windshield_top - 0.1).min(windshield_base - proportions.front_door_m);
        let pillar = [pillar_front - 0.1, pillar_front];
        let pillar_middle = pillar_front - 0.05;
        let rear_door_end = pillar_middle - proportions.rear_door_m;
        let greenhouse_rear = match body {
            BodyType::Sedan => {
                // The boot deck is a fifth of the length, the backlight leans 55° from the vertical (ours).
                let deck = rear_face + 0.2 * length_m - BUMPER_DEPTH_M;
                [deck, deck + (height_m - bonnet_height_m) * 55f64.to_radians().tan()]
            }
            BodyType::Pickup => [rear_door_end; 2],
            BodyType::Suv | BodyType::Van | BodyType::Bus => [rear_face; 2],
        };
        if pillar[0] < greenhouse_rear[1] + 0.2 {
            return Err(format!(
                "windshield_rake_deg {windshield_rake_deg}: with bonnet_length_m {bonnet_length_m} and height_m {height_m} the windshield reaches too far back for a {}'s roof and doors (length_m {length_m})",
                body.name()
            ));
        }
        let no_boot = body == BodyType::Sedan && greenhouse_rear[0] < rear_face + 0.3;
        if rear_door_end < rear_face + 0.5 || no_boot {
            return Err(format!(
                "length_m {length_m} is too short for a {}'s doors behind bonnet_length_m {bonnet_length_m}",
                body.name()
            ));
        }
        let bed_floor = (bonnet_height_m - 0.5).max(arch_top + 0.05);
        if body == BodyType::Pickup && bed_floor > bonnet_height_m - 0.1 {
            return Err(format!(
                "bonnet_height_m {bonnet_height_m} leaves the pickup's bed less than 0.1 m deep above its wheel arches"
            ));
        }
        Ok(Layout {
            body,
            dims: *dims,
            proportions,
            half_length,
            half_width: width_m / 2.0,
            front_face,
            rear_face,
            windshield_base,
            windshield_top,
            pillar,
            rear_door_end,
            greenhouse_rear,
            axles: [wheelbase_m / 2.0, -wheelbase_m / 2.0],
            arch_top,
            bed_floor,
        })
    }

    /// The x range of each wheel arch, front then rear.
    pub(crate) fn arches(&self) -> [[f64; 2]; 2] {
        let reach = self.proportions.wheel[0] + ARCH_CLEARANCE_M;
        self.axles.map(|x| [x - reach, x + reach])
    }

    /// How far in from the body side each arch's inner wall stands.
    pub(crate) fn arch_depth(&self) -> f64 {
        2.0 * self.proportions.wheel[2] + 0.08
    }
}

/// The belt above the wheel arches and below the roof, the wheels within the
/// width and the length; the arches' height.
fn check_wheels(body: BodyType, dims: &BodyDims, proportions: &Proportions) -> Result<f64, String> {
    let BodyDims { length_m, width_m, height_m, bonnet_height_m, wheelbase_m, .. } = *dims;
    let [radius, _, half_tyre] = proportions.wheel;
    let arch_top = 2.0 * radius + ARCH_CLEARANCE_M;
    if bonnet_height_m < arch_top + 0.1 {
        return Err(format!(
            "bonnet_height_m {bonnet_height_m} is too low: a {}'s wheel arches reach {arch_top:.3} m, and the belt must be at least 0.1 m above them",
            body.name()
        ));
    }
    if height_m - bonnet_height_m < 0.3 {
        return Err(format!(
            "bonnet_height_m {bonnet_height_m} leaves less than 0.3 m of windows below height_m {height_m}"
        ));
    }
    if 4.0 * half_tyre + 0.4 > width_m {
        return Err(format!("width_m {width_m} is too narrow for a {}'s wheels", body.name()));
    }
    let overhang = (length_m - wheelbase_m) / 2.0;
    let needed = radius + ARCH_CLEARANCE_M + PLATE_DEPTH_M + BUMPER_DEPTH_M + 0.1;
    if overhang < needed {
        return Err(format!(
            "wheelbase_m {wheelbase_m} leaves {overhang:.3} m from an axle to the end of length_m {length_m}; a {}'s wheels need {needed:.3} m",
            body.name()
        ));
    }
    Ok(arch_top)
}

/// Each field finite and within what a road vehicle can have.
fn check_ranges(dims: &BodyDims) -> Result<(), String> {
    let ranges = [(2.0, 25.0), (1.0, 3.0), (1.0, 5.0), (0.05, 5.0), (0.4, 4.0), (0.0, 75.0), (1.0, 20.0)];
    for ((name, value), (lo, hi)) in dims.fields().into_iter().zip(ranges) {
        if !(value.is_finite() && (lo..=hi).contains(&value)) {
            return Err(format!("{name} must be between {lo} and {hi}, not {value}"));
        }
    }
    if dims.wheelbase_m >= dims.length_m {
        return Err(format!(
            "wheelbase_m {} must be shorter than length_m {}",
            dims.wheelbase_m, dims.length_m
        ));
    }
    if dims.bonnet_length_m >= dims.length_m / 2.0 {
        return Err(format!(
            "bonnet_length_m {} must be under half of length_m {}",
            dims.bonnet_length_m, dims.length_m
        ));
    }
    if dims.bonnet_height_m >= dims.height_m {
        return Err(format!(
            "bonnet_height_m {} must be below height_m {}",
            dims.bonnet_height_m, dims.height_m
        ));
    }
    Ok(())
}
