//! Several measured vehicles in one scene (issue 43 §3): a scene file's own
//! `vehicle` and the `vehicle` occluders marked `"measure": NAME`. Each is
//! measured in a pass of its own (`Scene::measuring`, [`crate::scene::fleet_pass`]): the same scene, in
//! which that vehicle carries the palette and every other one, the scene's
//! own vehicle included, is an ordinary moving occluder on its own path. A
//! pass is an ordinary one-vehicle scene, so every capture, count and
//! measure runs on it unchanged, and a vehicle's numbers are those of a
//! capture of it alone with the others as occluders, exact by construction
//! (k vehicles cost k captures). Names become folder names, so they are
//! checked here: short, plain, unique. This module names the fleet and
//! depends on no scene (the scene file reads it); the passes are built in
//! [`crate::scene::fleet_pass`].

use std::path::Path;

use crate::error::{CaptureError, Result};
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
