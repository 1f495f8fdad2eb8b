//! Several measured vehicles in one scene (issue 43 §3): a scene file's own
//! `vehicle` and the `vehicle` occluders marked `"measure": NAME`. Each is
//! measured in a pass of its own ([`Scene::measuring`]): the same scene, in
//! which that vehicle carries the palette and every other one, the scene's
//! own vehicle included, is an ordinary moving occluder on its own path. A
//! pass is an ordinary one-vehicle scene, so every capture, count and
//! measure runs on it unchanged, and a vehicle's numbers are those of a
//! capture of it alone with the others as occluders, exact by construction
//! (k vehicles cost k captures). Names become folder names, so they are
//! checked here: short, plain, unique.

use std::path::Path;

use crate::error::{CaptureError, Result};
use crate::scene::moving::{FollowOffset, MovingOccluder, OccluderPath};
use crate::scene::scene_file::Scene;
use crate::scene::vehicle::VehicleSpec;

/// The name of the scene's own vehicle when the file gives it none.
pub const DEFAULT_VEHICLE_NAME: &str = "vehicle";

/// Longest vehicle name: a folder name on every file system.
const MAX_NAME_LEN: usize = 64;

/// Folder names an archive keeps for itself, or that `ufcsr analyze` does
/// not search for archives: no vehicle may take them.
const RESERVED_NAMES: [&str; 3] = ["tiles", "results", "shards"];

/// One measured vehicle of a scene.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FleetVehicle {
    /// Its `measure` name: its archive is `OUT/NAME`.
    pub name: String,
    /// Where the scene file gives it: `vehicle` or `occluders[N]`.
    pub source: String,
    /// Its place in `Occluders::moving`; `None` for the scene's own vehicle.
    pub moving: Option<usize>,
    /// Its model in words where it has one of its own (the scene's own
    /// vehicle, an occluder's `model`); `None` for a copy of the scene's.
    pub described: Option<String>,
}

/// The fleet of a scene file at `path`: empty when no occluder is measured,
/// else the scene's own vehicle (`own`, `described`; named by its `measure`,
/// default [`DEFAULT_VEHICLE_NAME`]) and the `measured` occluders, every
/// name checked and unique.
pub(crate) fn fleet(
    path: &Path,
    own: &VehicleSpec,
    described: &str,
    measured: Vec<FleetVehicle>,
) -> Result<Vec<FleetVehicle>> {
    let own_name = own.measure.as_deref();
    let own = FleetVehicle {
        name: own_name.unwrap_or(DEFAULT_VEHICLE_NAME).to_string(),
        source: "vehicle".into(),
        moving: None,
        described: Some(described.to_string()),
    };
    if let Some(name) = own_name {
        check_name(name)
            .map_err(|problem| CaptureError::bad_file(path, format!("vehicle.measure: {problem}")))?;
    }
    if measured.is_empty() {
        return Ok(Vec::new());
    }
    let fleet: Vec<FleetVehicle> = std::iter::once(own).chain(measured).collect();
    for (k, vehicle) in fleet.iter().enumerate().skip(1) {
        check_name(&vehicle.name).map_err(|problem| {
            CaptureError::bad_file(path, format!("{}: measure: {problem}", vehicle.source))
        })?;
        // Folder names: two that differ only in case are one folder on some file systems.
        if let Some(first) = fleet[..k].iter().find(|other| other.name.eq_ignore_ascii_case(&vehicle.name)) {
            return Err(CaptureError::bad_file(
                path,
                format!(
                    "{}: measure {:?} names a vehicle {} already names ({:?}): each measured vehicle needs a \
                     name of its own, its archive's folder (the scene's own vehicle is {:?} unless \
                     vehicle.measure names it)",
                    vehicle.source, vehicle.name, first.source, first.name, DEFAULT_VEHICLE_NAME
                ),
            ));
        }
    }
    Ok(fleet)
}

/// A vehicle's name, checked as a folder name: 1 to 64 ASCII letters,
/// digits, `-`, `_` or `.`, starting with a letter or digit, not one an
/// archive keeps for itself.
fn check_name(name: &str) -> std::result::Result<(), String> {
    let plain = name.chars().all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c));
    let starts = name.chars().next().is_some_and(|c| c.is_ascii_alphanumeric());
    if !(plain && starts && name.len() <= MAX_NAME_LEN) {
        return Err(format!(
            "{name:?} is not a plain folder name: give 1 to {MAX_NAME_LEN} ASCII letters, digits, '-', '_' or \
             '.', starting with a letter or digit"
        ));
    }
    if RESERVED_NAMES.iter().any(|reserved| reserved.eq_ignore_ascii_case(name)) {
        return Err(format!(
            "{name:?} is a folder an archive keeps for itself ({})",
            RESERVED_NAMES.join(", ")
        ));
    }
    Ok(())
}

impl Scene {
    /// The scene of the pass that measures fleet vehicle `which` (an index
    /// into [`Scene::fleet`]): an ordinary one-vehicle scene. For the scene's
    /// own vehicle it is the scene as it is (the others stay the moving
    /// occluders they are); for another, that vehicle is measured on its own
    /// path and the scene's own vehicle takes its place among the moving
    /// occluders, driven along the scenario's motion. Its manifest names the
    /// vehicle (`scene.measured`).
    pub fn measuring(&self, which: usize) -> Result<Scene> {
        let names: Vec<String> = self.fleet.iter().map(|vehicle| vehicle.name.clone()).collect();
        let member = self.fleet.get(which).ok_or_else(|| {
            CaptureError::BadOptions(format!(
                "no measured vehicle #{which}; the scene measures {}",
                names.join(", ")
            ))
        })?;
        let mut pass = self.clone();
        pass.fleet = Vec::new();
        if let Some(index) = member.moving {
            let own = MovingOccluder {
                name: format!("vehicle {}", self.fleet[0].name),
                mesh: self.vehicle.clone(),
                path: OccluderPath::Follow(FollowOffset::default()),
            };
            let other = std::mem::replace(&mut pass.occluders.moving[index], own);
            pass.vehicle = other.mesh;
            pass.vehicle_path = Some(other.path);
        }
        pass.info.moving_occluders = Some(pass.occluders.moving.iter().map(|m| m.name.clone()).collect());
        pass.info.vehicle = Some(match (&member.described, &self.info.vehicle) {
            (Some(described), _) => format!("{}: {described}", member.name),
            (None, Some(own)) => format!("{}: a copy of {own}", member.name),
            (None, None) => member.name.clone(),
        });
        pass.info.measured = Some(ufcsr::format::MeasuredRecord {
            fleet: names,
            name: member.name.clone(),
            source: member.source.clone(),
        });
        Ok(pass)
    }

    /// Refuses a scene that measures several vehicles for a command that
    /// measures one (`what` names it), saying how to measure each.
    pub fn refuse_fleet(&self, what: &str) -> Result<()> {
        if self.fleet.is_empty() {
            return Ok(());
        }
        let names: Vec<&str> = self.fleet.iter().map(|vehicle| vehicle.name.as_str()).collect();
        Err(CaptureError::BadOptions(format!(
            "scene {} measures {} vehicles ({}): {what} measures one vehicle; capture them with `ufcsr capture \
             scene FILE --out OUT` (one archive per vehicle, OUT/NAME), or give this command a scene in which \
             only one vehicle has `measure`",
            self.info.file.as_deref().unwrap_or(&self.name),
            names.len(),
            names.join(", ")
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vehicle_names_are_plain_folder_names_and_not_an_archives_own() {
        assert!(check_name("lead-car_2.b").is_ok());
        for bad in ["", "../up", "a/b", ".hidden", "-x", "car one", "é", "results", "Tiles", &"x".repeat(65)]
        {
            assert!(check_name(bad).is_err(), "{bad:?}");
        }
    }
}
