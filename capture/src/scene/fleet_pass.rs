//! The pass of one measured vehicle of a fleet ([`crate::scene::fleet`]):
//! the scene in which that vehicle carries the palette and every other one,
//! the scene's own vehicle included, is an ordinary moving occluder. Apart
//! from the fleet's names so that the scene file, which reads the names,
//! and the passes, which read the scene, form no module cycle.

use crate::error::{CaptureError, Result};
use crate::scene::moving::{FollowOffset, MovingOccluder, OccluderPath};
use crate::scene::scene_file::Scene;

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
