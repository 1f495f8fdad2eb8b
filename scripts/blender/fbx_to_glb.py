"""FBX to binary glTF for ufcsr capture, through Blender's own FBX importer.

Why: FBX is Unity's and most vendors' format, ufcsr reads glTF and OBJ, and
no maintained Rust FBX reader exists; Blender's importer is the reference.
The conversion keeps what a capture depends on:

- units: the importer applies the file's UnitScaleFactor, so the glTF is in
  metres whatever the FBX's unit (centimetres from 3ds Max/Unity exports);
- axes: the importer reads the file's UpAxis/FrontAxis into Blender's Z-up
  world, the exporter writes glTF's Y-up (`export_yup`), which is what
  ufcsr's default `axes` read; check forward with `ufcsr inspect`;
- node transforms: objects, their parents and transforms become glTF nodes
  (modifiers are not applied, nothing is flattened);
- material names and the model's own UVs (TEXCOORD_0), for
  `"parts_from": "material"` or a part map painted over those UVs; textures
  are left out (`--images` keeps them).

It also writes NAME.report.json beside NAME.glb (or --report): per object its
parent, world matrix, triangles, whether it has UVs, and per material slot
the polygons that use it, so material slots assigned to no polygon (a
model whose parts are named by unused slots) show before a capture.

Run with the bpy module (pip install bpy==4.2.0 under Python 3.11) or in
Blender:

    python fbx_to_glb.py car.fbx car.glb [--report car.report.json] [--images]
    blender -b -P fbx_to_glb.py -- car.fbx car.glb

Exit codes: 0 written, 2 bad input (the message names the file), 1 other.
Nothing is written over the input, and the output is written to a
temporary name in its folder and renamed when complete.
"""

import argparse
import json
import os
import sys
import tempfile


class InputError(Exception):
    """Bad input: exit code 2, the message names the file."""


def arguments(argv):
    parser = argparse.ArgumentParser(prog="fbx_to_glb.py", description=__doc__.split("\n\n")[0])
    parser.add_argument("fbx", help="the FBX file to convert")
    parser.add_argument("glb", help="the binary glTF to write (.glb)")
    parser.add_argument("--report", help="the JSON report to write (default: GLB's name with .report.json)")
    parser.add_argument("--images", action="store_true", help="embed the textures too (default: none)")
    return parser.parse_args(argv)


# Size cap for the FBX read, as the analyzer's for models (MODEL_LIMIT, docs/reliability.md).
FBX_LIMIT = 1 << 30


def check_paths(fbx, glb, report):
    """The input a regular file (links resolved) within the cap; the outputs new or regular files,
    never a link, a device or a FIFO (the result is renamed over them), never the input."""
    if not os.path.isfile(fbx):
        raise InputError(f"{fbx}: not a regular file")
    size = os.stat(fbx).st_size
    if size > FBX_LIMIT:
        raise InputError(f"{fbx}: {size:,} bytes, more than the {FBX_LIMIT:,} bytes allowed")
    if not fbx.lower().endswith(".fbx"):
        raise InputError(f"{fbx}: not an .fbx file")
    if not glb.lower().endswith(".glb"):
        raise InputError(f"{glb}: the output must end in .glb (binary glTF)")
    for out in (glb, report):
        if os.path.islink(out):
            raise InputError(f"{out}: is a link; refusing to write through it")
        if os.path.lexists(out) and not os.path.isfile(out):
            raise InputError(f"{out}: is not a regular file (a folder, device, FIFO or socket); refusing to replace it")
        if os.path.exists(out) and os.path.samefile(out, fbx):
            raise InputError(f"{out}: is the input; refusing to write over it")
    if os.path.abspath(glb) == os.path.abspath(report):
        raise InputError(f"{glb}: the report would replace the model; give --report another name")
    for out in (glb, report):
        folder = os.path.dirname(os.path.abspath(out))
        if not os.path.isdir(folder):
            raise InputError(f"{out}: its folder {folder} does not exist")


def import_fbx(bpy, fbx):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.unit_settings.system = "METRIC"
    scene.unit_settings.scale_length = 1.0
    try:
        result = bpy.ops.import_scene.fbx(filepath=os.path.abspath(fbx), use_custom_normals=True, use_anim=False)
    except RuntimeError as error:
        # Blender's operators raise RuntimeError on a file they cannot parse (a corrupt FBX).
        raise InputError(f"{fbx}: Blender's FBX importer could not read it ({error})") from None
    if "FINISHED" not in result:
        raise InputError(f"{fbx}: Blender's FBX importer could not read it ({result})")
    meshes = [o for o in scene.objects if o.type == "MESH"]
    if not meshes:
        raise InputError(f"{fbx}: holds no mesh")
    return meshes


def object_report(obj):
    mesh = obj.data
    mesh.calc_loop_triangles()
    slots = [slot.material.name if slot.material else None for slot in obj.material_slots]
    used = {}
    for polygon in mesh.polygons:
        name = slots[polygon.material_index] if polygon.material_index < len(slots) else None
        used[name or "(none)"] = used.get(name or "(none)", 0) + 1
    return {
        "name": obj.name,
        "parent": obj.parent.name if obj.parent else None,
        "matrix_world": [list(row) for row in obj.matrix_world],
        "triangles": len(mesh.loop_triangles),
        "uvs": len(mesh.uv_layers) > 0,
        "material_slots": [s or "(empty)" for s in slots],
        "polygons_per_material": used,
    }


def bounds(meshes):
    import mathutils  # Blender's module

    low, high = [float("inf")] * 3, [float("-inf")] * 3
    for obj in meshes:
        for corner in obj.bound_box:
            world = obj.matrix_world @ mathutils.Vector(corner)
            for k in range(3):
                low[k], high[k] = min(low[k], world[k]), max(high[k], world[k])
    return low, high


def export_glb(bpy, glb, images):
    folder = os.path.dirname(os.path.abspath(glb))
    handle, temporary = tempfile.mkstemp(prefix=".fbx_to_glb-", suffix=".glb", dir=folder)
    os.close(handle)
    try:
        options = dict(
            filepath=temporary,
            export_format="GLB",
            export_yup=True,
            export_apply=False,
            export_texcoords=True,
            export_normals=True,
            export_materials="EXPORT",
            export_animations=False,
            use_selection=False,
        )
        if not images:
            options["export_image_format"] = "NONE"
        result = bpy.ops.export_scene.gltf(**options)
        if "FINISHED" not in result:
            raise RuntimeError(f"Blender's glTF exporter failed ({result})")
        os.replace(temporary, glb)
    finally:
        if os.path.exists(temporary):
            os.remove(temporary)


def write_json(path, value):
    folder = os.path.dirname(os.path.abspath(path))
    handle, temporary = tempfile.mkstemp(prefix=".fbx_to_glb-", suffix=".json", dir=folder)
    with os.fdopen(handle, "w") as out:
        json.dump(value, out, indent=2)
        out.write("\n")
    os.replace(temporary, path)


def convert(fbx, glb, report, images=False):
    import bpy  # Blender's module: only here, so the file rules are testable without it

    check_paths(fbx, glb, report)
    meshes = import_fbx(bpy, fbx)
    objects = [object_report(obj) for obj in meshes]
    low, high = bounds(meshes)
    unused = sorted(
        {slot for o in objects for slot in o["material_slots"]}
        - {name for o in objects for name in o["polygons_per_material"]}
    )
    export_glb(bpy, glb, images)
    summary = {
        "fbx": fbx,
        "glb": glb,
        "blender": bpy.app.version_string,
        # Blender world, metres, Z up (the glb is Y up: glTF y = Blender z, glTF z = -Blender y).
        "bounds_m_blender_z_up": {"min": low, "max": high},
        "objects": objects,
        "material_slots_used_by_no_polygon": unused,
    }
    write_json(report, summary)
    return summary


def main(argv):
    args = arguments(argv)
    report = args.report or os.path.splitext(args.glb)[0] + ".report.json"
    try:
        summary = convert(args.fbx, args.glb, report, args.images)
    except InputError as error:
        print(f"fbx_to_glb.py: {error}", file=sys.stderr)
        return 2
    except OSError as error:
        # A write that failed (no space, a folder gone): the message names the file.
        print(f"fbx_to_glb.py: {error}", file=sys.stderr)
        return 2
    except ImportError as error:
        print(f"fbx_to_glb.py: needs Blender's bpy module ({error}): pip install bpy==4.2.0 into a Python 3.11 "
              "venv, or run it in Blender: blender -b -P fbx_to_glb.py -- IN.fbx OUT.glb", file=sys.stderr)
        return 1
    size = [h - l for l, h in zip(*summary["bounds_m_blender_z_up"].values())]
    triangles = sum(o["triangles"] for o in summary["objects"])
    print(f"wrote {args.glb}: {len(summary['objects'])} objects, {triangles} triangles, "
          f"{size[0]:.3f} × {size[1]:.3f} × {size[2]:.3f} m (Blender x, y, z)")
    print(f"wrote {report}")
    if summary["material_slots_used_by_no_polygon"]:
        print("note: material slots used by no polygon (parts_from material cannot see them; paint a part map "
              "over the model's UVs instead): " + ", ".join(summary["material_slots_used_by_no_polygon"]))
    return 0


if __name__ == "__main__":
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    code = main(argv)
    sys.stdout.flush()
    os._exit(code)  # bpy may crash while Python shuts down
