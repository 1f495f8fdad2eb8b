//! Entry points for fuzzing the capture's input files, as
//! `ufcsr::fuzz_entry` does for the analyzer's: each takes arbitrary bytes as
//! one kind of file and must return, with an error if the bytes are bad,
//! never panic, hang or allocate without bound. The cargo-fuzz targets in
//! `fuzz/` call them, and `capture/tests/it/fuzz_regressions.rs` feeds them
//! the saved seeds and every input that once failed, on stable Rust.
//!
//! The files an input names (meshes, buffers, `mtllib`, a Unity export) are
//! looked for beside a path in a folder that does not exist, so only the
//! bytes given are parsed; an OBJ's `mtllib` reads the input itself as MTL.
//! A design file is planned without reading what it names; a `task.json` is
//! checked as `design merge` checks it, against the shipped tiny design.

use std::path::Path;

use crate::scene::mesh::{Axes, PartSource, check_model, gltf_mesh, obj_mesh, obj_options};
use crate::scene::scene_file::Scene;

/// The folder fuzzed files seem to be in: absent, so nothing beside them is read.
const NOWHERE: &str = "/nonexistent-ufcsr-fuzz";

/// A scene file (`"mesh": "demo"` builds the demo truck; other meshes do not exist).
pub fn scene(bytes: &[u8]) {
    let _ = Scene::parse(&Path::new(NOWHERE).join("scene.json"), bytes);
}

/// A glTF (`.gltf` with data: URIs) or GLB model, loaded as a vehicle.
pub fn gltf(bytes: &[u8]) {
    let path = Path::new(NOWHERE).join("model.glb");
    let Ok(model) = ufcsr::files::parse_gltf(&path, bytes, ufcsr::files::MODEL_LIMIT) else { return };
    if let Ok(mesh) = gltf_mesh(&path, &model, PartSource::Node, &Axes::default()) {
        let _ = check_model(&path, &mesh);
    }
}

/// An OBJ loaded as a vehicle, parts by material; every `mtllib` it names
/// reads the same bytes as an MTL file.
pub fn obj(bytes: &[u8]) {
    let path = Path::new(NOWHERE).join("model.obj");
    let read_material = |_: &Path| Ok(bytes.to_vec());
    let Ok((models, materials)) =
        crate::scene::model_files::obj_from_bytes(&path, bytes, &obj_options(), read_material)
    else {
        return;
    };
    if let Ok(mesh) = obj_mesh(models, &materials, PartSource::Material, &Axes::default()) {
        let _ = check_model(&path, &mesh);
    }
}

/// A Unity scenario export (`unity-intersection.json`).
pub fn unity(bytes: &[u8]) {
    let _ = crate::scene::unity::parse(&Path::new(NOWHERE).join("unity.json"), bytes);
}

/// A design file: parsed, its version checked, its levels checked and its crossing counted and
/// planned into tasks (nothing it names is read: that is `check_inputs`, which loads models).
pub fn design(bytes: &[u8]) {
    let path = Path::new(NOWHERE).join("design.json");
    let Ok(design) = ufcsr::format::parse_json::<ufcsr::format::Design>(&path, bytes, "design") else {
        return;
    };
    if ufcsr::format::check_version(&path, &design.schema, ufcsr::format::DESIGN_SCHEMA).is_ok() {
        let _ = crate::design::plan::plan_checked(design, &path);
    }
}

/// The shipped tiny design's plan and its cells' bounds, built once: the design a fuzzed
/// `task.json` is checked against.
fn tiny_design() -> Option<&'static (crate::design::plan::Plan, crate::design::checks::CellLimits)> {
    static TINY: std::sync::OnceLock<Option<(crate::design::plan::Plan, crate::design::checks::CellLimits)>> =
        std::sync::OnceLock::new();
    TINY.get_or_init(|| {
        let path = Path::new(NOWHERE).join("tiny-2x2.json");
        let bytes = include_bytes!("../../fixtures/designs/tiny-2x2.json");
        let design = ufcsr::format::parse_json::<ufcsr::format::Design>(&path, bytes, "design").ok()?;
        let plan = crate::design::plan::plan_checked(design, &path).ok()?;
        let limits = crate::design::checks::check_inputs(&plan).ok()?;
        Some((plan, limits))
    })
    .as_ref()
}

/// A `task.json` as `design merge` reads it: parsed, its version checked, then every value,
/// unit and input record checked against the tiny design's cells (its hash and place are not
/// required to match, so the checks past them are reached).
pub fn design_task(bytes: &[u8]) {
    let path = Path::new(NOWHERE).join("tasks/task-0000/task.json");
    let Ok(task) = ufcsr::format::parse_json::<ufcsr::format::DesignTask>(&path, bytes, "design task") else {
        return;
    };
    if ufcsr::format::check_version(&path, &task.schema, ufcsr::format::DESIGN_TASK_SCHEMA).is_err() {
        return;
    }
    let Some((plan, limits)) = tiny_design() else { return };
    let _ = crate::design::task_checks::check_tasks(
        plan,
        Path::new(NOWHERE),
        std::slice::from_ref(&task),
        limits,
    );
}
