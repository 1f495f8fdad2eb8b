//! The vehicle of a scene file, built one way for `capture` and `inspect`:
//! load the mesh (or build the body of the family that `body` and `dims`
//! name; with `axes`: origin, scale, forward and up), name its parts (by
//! node, mesh or material, or through a part map painted over its own UVs:
//! [`crate::scene::part_map`]), apply `rename`, then the region rules of
//! `parts`, then check its size and origin.
//!
//! The checks only warn: a 40 s capture of a vehicle that is ten times too
//! small, lies on its side or pivots at its front bumper is wasted, but the
//! scene may mean it (a toy car, a trailer hitched at its front).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use glam::{DVec3, dvec3};
use serde::{Deserialize, Serialize};

use crate::error::{CaptureError, Result};
use crate::scene::demo;
use crate::scene::family::{BodyDims, BodyType, body_mesh};
use crate::scene::mesh::{Axes, Mesh, PartSource, load_model};
use crate::scene::part_map::{self, PartMapReport, PartMapSpec};
use crate::scene::regions::{self, PartRule, RegionReport};

/// The vehicle: a mesh file, the demo truck, or a body of the family.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleSpec {
    /// `.glb`, `.gltf` or `.obj`, or `"demo"` for the built-in truck; left
    /// out when `body` names a body of the family.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub mesh: String,
    /// A body of the parametric family (`sedan`, `suv`, `van`, `pickup`,
    /// `bus`; docs/vehicles.md) instead of a mesh.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body: Option<String>,
    /// The body's dimensions; those left out take the body's typical values.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dims: Option<ufcsr::format::BodyDimsOverride>,
    /// What names the parts: `node` (default), `mesh` or `material`, or
    /// `{"part_map": PNG, "legend": CSV}` painted over the model's own UVs.
    #[serde(default)]
    pub parts_from: PartsFrom,
    /// Renames parts (`from → to`); several names may map to one part.
    #[serde(default)]
    pub rename: BTreeMap<String, String>,
    /// Which file axes are forward and up, the scale to metres and the origin.
    #[serde(default)]
    pub axes: Axes,
    /// Parts by region, applied after `rename` (see [`crate::scene::regions`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub parts: Vec<PartRule>,
    /// The vehicle's real length: warn when it is off by more than 20 %.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub expect_length_m: Option<f64>,
    /// Its name where the scene measures several vehicles (a `vehicle`
    /// occluder with `measure`): its archive is `OUT/NAME`; default `vehicle`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measure: Option<String>,
}

/// What names the vehicle's parts.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged, try_from = "serde_json::Value")]
pub enum PartsFrom {
    /// A name of the file: node, mesh or material.
    Names(PartSource),
    /// A part map over the model's own UVs ([`crate::scene::part_map`]).
    PartMap(PartMapSpec),
}

impl Default for PartsFrom {
    fn default() -> PartsFrom {
        PartsFrom::Names(PartSource::default())
    }
}

impl TryFrom<serde_json::Value> for PartsFrom {
    type Error = String;

    fn try_from(value: serde_json::Value) -> std::result::Result<PartsFrom, String> {
        let shape = "\"node\", \"mesh\", \"material\" or {\"part_map\": \"PNG\", \"legend\": \"CSV\"}";
        match value {
            serde_json::Value::String(_) => serde_json::from_value(value)
                .map(PartsFrom::Names)
                .map_err(|_| format!("parts_from must be {shape}")),
            serde_json::Value::Object(_) => serde_json::from_value(value)
                .map(PartsFrom::PartMap)
                .map_err(|error| format!("parts_from: {error} (expected {shape})")),
            other => Err(format!("parts_from must be {shape}, not {other}")),
        }
    }
}

/// The body of the family `spec` names, with its dimensions (`None`: a
/// mesh); `scene` names the file in errors.
pub(crate) fn family_body(spec: &VehicleSpec, scene: &Path) -> Result<Option<(BodyType, BodyDims)>> {
    let Some(name) = &spec.body else {
        if spec.dims.is_some() {
            return Err(CaptureError::bad_file(scene, "vehicle.dims needs vehicle.body"));
        }
        if spec.mesh.is_empty() {
            return Err(CaptureError::bad_file(scene, "the vehicle needs a mesh or a body"));
        }
        return Ok(None);
    };
    if !spec.mesh.is_empty() {
        return Err(CaptureError::bad_file(scene, "the vehicle has a mesh and a body: give one"));
    }
    let Some(body) = BodyType::parse(name) else {
        let names: Vec<&str> = BodyType::ALL.iter().map(|b| b.name()).collect();
        return Err(CaptureError::bad_file(
            scene,
            format!("vehicle.body {name:?} is not one of {}", names.join(", ")),
        ));
    };
    let dims = BodyDims::typical(body).with(&spec.dims.unwrap_or_default());
    Ok(Some((body, dims)))
}

/// How far the vehicle's length may be from `expect_length_m` before a warning.
pub(crate) const LENGTH_TOLERANCE: f64 = 0.2;

/// A built vehicle and what was noticed on the way.
#[derive(Debug, Clone)]
pub(crate) struct Vehicle {
    pub mesh: Mesh,
    /// What the region rules did (empty without rules).
    pub regions: RegionReport,
    /// Size, axes and origin doubts, rules that matched nothing.
    pub warnings: Vec<String>,
    /// The files read: the mesh and the buffers or MTL files it names
    /// (none for the demo truck), and a part map and its legend.
    pub files: Vec<PathBuf>,
    /// What labelling through a part map found (`parts_from.part_map`).
    pub part_map: Option<PartMapReport>,
}

/// Builds the vehicle of `spec`; mesh paths are relative to `base`, and
/// `scene` names the file in errors.
pub(crate) fn build(spec: &VehicleSpec, base: &Path, scene: &Path) -> Result<Vehicle> {
    let names = match &spec.parts_from {
        PartsFrom::Names(source) => *source,
        PartsFrom::PartMap(map) => map.names,
    };
    let (mut mesh, mut files) = if let Some((body, dims)) = family_body(spec, scene)? {
        let mesh = body_mesh(body, &dims)
            .map_err(|e| CaptureError::bad_file(scene, format!("vehicle.dims: {e}")))?;
        (mesh, Vec::new())
    } else if spec.mesh == "demo" {
        (demo::truck(), Vec::new())
    } else {
        load_model(&base.join(&spec.mesh), names, &spec.axes)?
    };
    let part_map = match &spec.parts_from {
        PartsFrom::PartMap(map) => {
            let report = part_map::apply(&mut mesh, map, base, scene)?;
            files.extend([report.part_map.clone(), report.legend.clone()]);
            Some(report)
        }
        PartsFrom::Names(_) => None,
    };
    mesh.rename_parts(&spec.rename);
    let regions = regions::apply(&mut mesh, &spec.parts, &spec.rename)
        .map_err(|message| CaptureError::bad_file(scene, format!("vehicle.parts: {message}")))?;
    if let Some(expected) = spec.expect_length_m
        && !(expected.is_finite() && expected > 0.0)
    {
        return Err(CaptureError::bad_file(
            scene,
            format!("vehicle.expect_length_m must be positive, not {expected}"),
        ));
    }
    let mut warnings = part_map.as_ref().map(PartMapReport::warnings).unwrap_or_default();
    warnings.extend(regions.warnings());
    warnings.extend(checks(&mesh, &spec.axes, spec.expect_length_m)?);
    Ok(Vehicle { mesh, regions, warnings, files, part_map })
}

/// The point the vehicle's origin should be at: on the ground (lowest
/// point) under the centre of its bounding box, in the vehicle frame.
pub(crate) fn ground_centre(mesh: &Mesh) -> DVec3 {
    let (min, max) = mesh.bounds();
    dvec3((min.x + max.x) / 2.0, (min.y + max.y) / 2.0, min.z)
}

/// Warnings about the vehicle's size, axes and origin.
pub(crate) fn checks(mesh: &Mesh, axes: &Axes, expect_length_m: Option<f64>) -> Result<Vec<String>> {
    let mut warnings = Vec::new();
    let (min, max) = mesh.bounds();
    let size = max - min;
    if let Some(expected) = expect_length_m {
        let off = size.x / expected - 1.0;
        if off.abs() > LENGTH_TOLERANCE {
            warnings.push(format!(
                "the vehicle is {:.3} m long but expect_length_m is {expected} m ({:+.0}%): check axes.scale (a file in centimetres needs 0.01, in inches 0.0254) and axes.forward",
                size.x,
                off * 100.0
            ));
        }
    }
    if size.y > size.x {
        warnings.push(format!(
            "the vehicle is wider ({:.2} m along y) than long ({:.2} m along x): is axes.forward ({}) right?",
            size.y, size.x, axes.forward
        ));
    }
    if size.z > size.x.max(size.y) {
        warnings.push(format!(
            "the vehicle is taller ({:.2} m along z) than long or wide: is axes.up ({}) right?",
            size.z, axes.up
        ));
    }
    // The rig places the vehicle by its origin and turns it about it, so the
    // origin should sit on the ground under the vehicle's middle.
    let centre = ground_centre(mesh);
    let off_centre = centre.x.abs() > 0.1 * size.x || centre.y.abs() > 0.1 * size.y;
    let off_ground = centre.z.abs() > (0.02 * size.z).max(0.05);
    if off_centre || off_ground {
        let suggested = axes.to_file(centre)?;
        warnings.push(format!(
            "the vehicle's origin is not on the ground under its centre (that point is at x {:+.3}, y {:+.3}, z {:+.3} m in the vehicle frame): poses place and turn the vehicle about its origin; set axes.origin to [{:.4}, {:.4}, {:.4}] (file units) to move it there",
            centre.x, centre.y, centre.z, suggested.x, suggested.y, suggested.z
        ));
    }
    Ok(warnings)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::vec3;

    #[test]
    fn size_axes_and_origin_checks_warn_with_a_fix() {
        let mut mesh = Mesh::default();
        mesh.add_box(vec3(-2.0, -1.0, 0.0), vec3(2.0, 1.0, 1.8), [Some("body"); 6]);
        let axes = Axes::default();
        assert!(checks(&mesh, &axes, Some(4.4)).unwrap().is_empty());
        let warnings = checks(&mesh, &axes, Some(6.0)).unwrap();
        assert_eq!(warnings.len(), 1);
        assert!(warnings[0].contains("4.000 m long") && warnings[0].contains("-33%"), "{}", warnings[0]);

        // Pivoting at the front bumper, 0.5 m above the ground: the fix is
        // the file point of the ground under the centre. glTF axes: the
        // vehicle's x is the file's z, its z the file's y.
        let mut bumper = Mesh::default();
        bumper.add_box(vec3(-4.0, -1.0, -0.5), vec3(0.0, 1.0, 1.3), [Some("body"); 6]);
        let axes = Axes { scale: 0.5, origin: [1.0, 2.0, 3.0], ..Axes::default() };
        let warnings = checks(&bumper, &axes, None).unwrap();
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        let suggested = axes.to_file(ground_centre(&bumper)).unwrap();
        assert!(warnings[0].contains("[1.0000, 1.0000, -1.0000]"), "{suggested} {}", warnings[0]);
        let convert = Axes { origin: suggested.to_array(), ..axes.clone() }.converter().unwrap();
        let moved = convert(axes.to_file(dvec3(-2.0, 0.0, -0.5)).unwrap().as_vec3().to_array());
        assert!(moved.length() < 1e-6, "{moved}");

        // Lying on its side: taller than long.
        let mut side = Mesh::default();
        side.add_box(vec3(-1.0, -1.0, 0.0), vec3(1.0, 1.0, 5.0), [Some("body"); 6]);
        assert!(checks(&side, &Axes::default(), None).unwrap()[0].contains("axes.up"));
    }
}
