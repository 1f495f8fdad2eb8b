//! FBX (Unity's and most vendors' format) reaches ufcsr through Blender:
//! `scripts/blender/fbx_to_glb.py`. Known answers on an FBX built here with
//! bpy (a 4 m × 1.8 m × 1.4 m body, in centimetres as Blender's FBX export
//! writes them, with a child mirror placed only by its node transform, two
//! materials on polygons and one slot used by none): the glb inspects as
//! 4.000 m long, 1.800 m wide, 1.600 m high (units, axes and the node
//! transform kept), `parts_from: material` gives the two materials, and the
//! report names the unused slot. Needs a Python with `bpy` (see blender.rs).

use std::path::Path;
use std::process::Command;

use crate::blender::bpy_python;
use crate::need::Outcome;
use libtest_mimic::Completion;

/// Builds the FBX with bpy: argv[-1] is the file to write.
const MAKE_FBX: &str = r#"
import bpy, os, struct, sys
bpy.ops.wm.read_factory_settings(use_empty=True)
def box(name, size, location, material, parent=None):
    bpy.ops.mesh.primitive_cube_add(size=1.0)
    obj = bpy.context.active_object
    obj.name = name
    for v in obj.data.vertices:  # the size in the mesh, the place in the transform
        v.co = (v.co.x * size[0], v.co.y * size[1], v.co.z * size[2])
    obj.location = location
    obj.data.materials.append(bpy.data.materials.new(material))
    obj.parent = parent
    return obj
# Blender's front is -Y: the body is 4 m along y.
body = box("body", (1.8, 4.0, 1.4), (0.0, 0.0, 0.7), "paint")
box("mirror", (0.2, 0.2, 0.2), (0.0, 0.0, 0.8), "mirror", parent=body)
body.data.materials.append(bpy.data.materials.new("door_unused"))
bpy.ops.export_scene.fbx(filepath=sys.argv[-1], object_types={"MESH"})
data = open(sys.argv[-1], "rb").read()
at = data.find(b"UnitScaleFactor")
at = data.find(b"D", at + len(b"UnitScaleFactor") + 24)
print("UnitScaleFactor", struct.unpack("<d", data[at + 1:at + 9])[0])
sys.stdout.flush()
os._exit(0)
"#;

fn script() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scripts/blender/fbx_to_glb.py")
}

pub fn fbx_to_glb_keeps_units_axes_node_transforms_and_material_names() -> Outcome {
    let python = match bpy_python() {
        Ok(python) => python,
        Err(outcome) => return outcome,
    };
    let dir = tempfile::tempdir().unwrap();
    let fbx = dir.path().join("car.fbx");
    let made = Command::new(&python).args(["-c", MAKE_FBX, fbx.to_str().unwrap()]).output().unwrap();
    let stdout = String::from_utf8_lossy(&made.stdout);
    assert!(made.status.success() && fbx.is_file(), "{stdout}{}", String::from_utf8_lossy(&made.stderr));
    assert!(stdout.contains("UnitScaleFactor 1.0"), "the FBX is in centimetres: {stdout}");

    let glb = dir.path().join("car.glb");
    let converted = Command::new(&python).arg(script()).args([&fbx, &glb]).output().unwrap();
    let said = String::from_utf8_lossy(&converted.stdout);
    assert!(converted.status.success(), "{said}{}", String::from_utf8_lossy(&converted.stderr));
    assert!(said.contains("door_unused"), "{said}");
    let report: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("car.report.json")).unwrap()).unwrap();
    assert_eq!(report["material_slots_used_by_no_polygon"], serde_json::json!(["door_unused"]));
    let mirror = report["objects"].as_array().unwrap().iter().find(|o| o["name"] == "mirror").unwrap();
    assert_eq!(mirror["parent"], "body");

    std::fs::write(
        dir.path().join("scene.json"),
        r#"{"vehicle": {"mesh": "car.glb", "parts_from": "material"}}"#,
    )
    .unwrap();
    let inspect = Command::new(env!("CARGO_BIN_EXE_ufcsr-capture"))
        .args(["inspect", dir.path().join("scene.json").to_str().unwrap(), "--out"])
        .arg(dir.path().join("inspect"))
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&inspect.stdout);
    assert!(inspect.status.success(), "{text}{}", String::from_utf8_lossy(&inspect.stderr));
    assert!(text.contains("size: 4.000 m long (x) × 1.800 m wide (y) × 1.600 m high (z)"), "{text}");
    let parts: Vec<&str> = text
        .lines()
        .filter(|l| l.ends_with("m²") && l.starts_with("  ") && !l.contains("surface"))
        .map(|l| l.split_whitespace().next().unwrap())
        .collect();
    assert_eq!(parts, ["paint", "mirror"], "{text}");

    // Bad input: exit 2, the file named, nothing written.
    let missing =
        Command::new(&python).arg(script()).args(["nowhere.fbx", "x.glb"]).current_dir(dir.path()).output();
    let missing = missing.unwrap();
    assert_eq!(missing.status.code(), Some(2), "{}", String::from_utf8_lossy(&missing.stderr));
    assert!(String::from_utf8_lossy(&missing.stderr).contains("nowhere.fbx: not a regular file"));
    assert!(!dir.path().join("x.glb").exists());
    Ok(Completion::Completed)
}
