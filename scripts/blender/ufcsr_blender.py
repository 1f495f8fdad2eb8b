#!/usr/bin/env python3
"""Renders a ufcsr capture archive's cameras again in Blender and writes a complete archive.

Why it exists: the capture path a researcher already uses is often Blender, and ufcsr capture's
archive describes itself (``manifest.json`` with every frame's vehicle pose and each eye's camera
and projection, ``vehicle.glb`` with the palette, ``scene.glb`` with the occluders, ``pidt.png``,
``parts.csv``), so Blender can render the very same frames. The result is an archive that
``ufcsr analyze OUT`` reads alone -- tiles, manifest with rig, fps, pixels per degree, projection,
poses, PIdT and legend -- and that ``cli/tests/external/blender.rs`` holds to ufcsr capture's own.

The colour recipe (docs/guide.md, "Unity and Blender captures") keeps every palette colour
unchanged on its way to the PNG: palette image ``sRGB`` with view transform ``Standard``, look
None, exposure 0, gamma 1, dither 0; Image Texture interpolation ``Closest`` into an Emission
shader; the world and the occluders the sRGB-decoded background ``#000FFF``; EEVEE 1 sample,
filter size 0 (default), or Cycles 1 sample, box filter 0.01, no denoising.

Runs with the ``bpy`` module (``pip install bpy==4.2.0``, Python 3.11)::

    python scripts/blender/ufcsr_blender.py --from ARCHIVE --out BLENDER_ARCHIVE

or inside Blender::

    blender -b -P scripts/blender/ufcsr_blender.py -- --from ARCHIVE --out BLENDER_ARCHIVE

Options: ``--engine eevee|cycles`` (default eevee), ``--frames 120,150`` or ``0-180/20`` (a subset
of the archive's frames; default all), ``--save-blend FILE.blend`` (the set-up scene at the first
frame, to open in Blender's UI), ``-q``. Bad input is an error naming the file and the problem
(exit 2); nothing is written outside ``--out`` but the ``--save-blend`` file.

Only the tiles the vehicle's bounding boxes touch are rendered (one Render Region per eye and
frame); the others can only show background and are listed empty, as the capture lists the tiles
it culls.
"""

import argparse
import json
import logging
import math
import os
import re
import stat
import struct
import sys
import time
import zlib

MANIFEST_SCHEMA = "ufcsr-manifest/1"
DEFAULT_BACKGROUND = "#000FFF"
TOOL = "ufcsr_blender.py"


class InputError(Exception):
    """Bad input: the message names the file and the problem."""


# ---------------------------------------------------------------- arguments and the manifest


def parse_arguments(argv):
    parser = argparse.ArgumentParser(
        prog=TOOL,
        description="Render a ufcsr capture archive's cameras again in Blender and write an "
        "archive that ufcsr analyze reads alone.",
    )
    parser.add_argument("--from", dest="source", required=True, metavar="ARCHIVE",
                        help="an archive written by ufcsr capture (its manifest.json has frames[].eyes)")
    parser.add_argument("--out", required=True, metavar="DIR", help="the new archive (absent or empty)")
    parser.add_argument("--engine", choices=["eevee", "cycles"], default="eevee")
    parser.add_argument("--frames", metavar="LIST",
                        help="frames to render: 120,150 or 0-180/20 (default: all of the archive's)")
    parser.add_argument("--save-blend", metavar="FILE", help="also save the set-up scene as a .blend")
    parser.add_argument("-q", "--quiet", action="store_true", help="print nothing but errors")
    return parser.parse_args(argv)


def frame_selection(spec):
    """The items of `120,150,0-180/20` as (first, last, step): a range is tested, never listed."""
    items = []
    for item in spec.split(","):
        item = item.strip()
        try:
            span, _, step = item.partition("/")
            first, _, last = span.partition("-")
            first = int(first)
            last = int(last) if last else first
            step = int(step) if step else 1
            if first < 0 or step < 1 or last < first or (step != 1 and first == last and "-" not in span):
                raise ValueError
        except ValueError:
            raise InputError(
                f"--frames {spec}: '{item}' is not a frame, a range FIRST-LAST or FIRST-LAST/STEP"
            )
        items.append((first, last, step))
    return items


# Size caps for what this script reads, as the analyzer's (docs/reliability.md).
MANIFEST_LIMIT = 256 << 20
COPIED_FILE_LIMIT = 1 << 30


def read_regular(path, limit):
    """The bytes of `path`: opened without blocking (a FIFO must not hang the
    script), a regular file once open (not a device or folder), at most `limit`
    bytes (a link to /dev/zero must not eat the memory); errors name the file."""
    try:
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except FileNotFoundError:
        raise InputError(f"{path}: not found")
    except OSError as error:
        raise InputError(f"{path}: cannot open ({error.strerror})")
    with os.fdopen(descriptor, "rb") as file:
        info = os.fstat(file.fileno())
        if not stat.S_ISREG(info.st_mode):
            raise InputError(f"{path}: not a regular file (a folder, device, FIFO or socket)")
        if info.st_size > limit:
            raise InputError(f"{path}: {info.st_size:,} bytes, more than the {limit:,} bytes allowed")
        data = file.read(limit + 1)
    if len(data) > limit:
        raise InputError(f"{path}: more than the {limit:,} bytes allowed")
    return data


def read_manifest(archive):
    """The manifest of `archive`, checked for what rebuilding the cameras needs."""
    path = os.path.join(archive, "manifest.json")
    try:
        manifest = json.loads(read_regular(path, MANIFEST_LIMIT))
    except InputError as error:
        if not os.path.lexists(path):
            raise InputError(f"{path}: not found (--from takes an archive written by ufcsr capture)")
        raise error
    except (UnicodeDecodeError, ValueError) as error:
        raise InputError(f"{path}: not readable JSON ({error})")
    except RecursionError:
        raise InputError(f"{path}: not readable JSON (nested too deeply)") from None
    if not isinstance(manifest, dict) or manifest.get("schema", MANIFEST_SCHEMA) != MANIFEST_SCHEMA:
        raise InputError(f"{path}: not a {MANIFEST_SCHEMA} manifest")
    frames = manifest.get("frames")
    if not isinstance(frames, list) or not frames:
        raise InputError(f"{path}: no 'frames' records (written by ufcsr capture only)")
    for index, record in enumerate(frames):
        check_frame(record, f"{path}: frames[{index}]")
    rig = manifest.get("rig")
    projection = rig.get("eye_projection") if isinstance(rig, dict) else None
    check_projection(projection, f"{path}: rig.eye_projection")
    for name in ("vehicle", "occluders", "pidt", "parts"):
        if not isinstance(manifest.get(name), str):
            raise InputError(f"{path}: no '{name}' file named (needed beside the tiles)")
        inside(archive, manifest[name], path)
    if isinstance(manifest.get("palette"), str):
        inside(archive, manifest["palette"], path)
    return manifest


def is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def is_vector(value, length=3):
    return isinstance(value, list) and len(value) == length and all(is_number(item) for item in value)


def check_frame(record, where):
    """A frame record names the vehicle's pose and each eye's camera."""
    if not isinstance(record, dict) or not isinstance(record.get("frame"), int) or record["frame"] < 0:
        raise InputError(f"{where}: no frame number")
    vehicle, eyes = record.get("vehicle"), record.get("eyes")
    if not isinstance(eyes, dict) or not isinstance(vehicle, dict):
        raise InputError(
            f"{where} (frame {record['frame']}) has no 'vehicle' pose or 'eyes' cameras: an archive from "
            "before ufcsr capture recorded them; capture it again"
        )
    if not is_vector(vehicle.get("position")) or not is_number(vehicle.get("yaw_deg")):
        raise InputError(f"{where}: 'vehicle' needs 'position' [x, y, z] and 'yaw_deg'")
    if not 1 <= len(eyes) <= 2:
        raise InputError(f"{where}: 'eyes' names {len(eyes)} eyes (one or two)")
    for name, eye in eyes.items():
        if not re.fullmatch(r"[A-Za-z0-9_-]{1,32}", name) or not isinstance(eye, dict):
            raise InputError(f"{where}: eye '{name}' is not a name with a camera")
        for key in ("position", "right", "up", "forward"):
            if not is_vector(eye.get(key)):
                raise InputError(f"{where}: eye '{name}' needs '{key}' as [x, y, z]")


def check_projection(projection, where):
    """The eyes' lens: rectilinear, a horizontal field of view, pixels, principal point, clip planes."""
    if not isinstance(projection, dict) or projection.get("model") != "rectilinear":
        raise InputError(f"{where}: missing or not 'rectilinear' (needed to rebuild the cameras)")
    pixels = projection.get("eye_pixels")
    sizes_ok = isinstance(pixels, list) and len(pixels) == 2
    if not (sizes_ok and all(isinstance(n, int) and 0 < n <= 65536 for n in pixels)):
        raise InputError(f"{where}: 'eye_pixels' is not [width, height]")
    fov = projection.get("horizontal_fov_deg")
    if not is_number(fov) or not 0 < fov < 180:
        raise InputError(f"{where}: 'horizontal_fov_deg' is not between 0 and 180")
    if not is_vector(projection.get("principal_point_px"), 2):
        raise InputError(f"{where}: 'principal_point_px' is not [x, y]")
    near, far = projection.get("near_m"), projection.get("far_m")
    if not (is_number(near) and is_number(far) and 0 < near < far):
        raise InputError(f"{where}: 'near_m' and 'far_m' are not 0 < near < far")


def inside(archive, relative, manifest_path):
    """`archive/relative` with links resolved, refused when it leaves the archive
    (also through a link), is not a regular file, or does not exist."""
    if os.path.isabs(relative) or ".." in relative.replace("\\", "/").split("/"):
        raise InputError(f"{manifest_path}: '{relative}' leaves the archive")
    path = os.path.join(archive, relative)
    real, root = os.path.realpath(path), os.path.realpath(archive)
    if os.path.commonpath([real, root]) != root:
        raise InputError(f"{manifest_path}: '{relative}' leads outside the archive (to {real}) through a link")
    if not os.path.lexists(path):
        raise InputError(f"{path}: named by {manifest_path} but missing")
    if not os.path.isfile(real):
        raise InputError(f"{path}: named by {manifest_path} but not a regular file")
    return real


def tile_grid(manifest, manifest_path):
    """(columns, rows, tile width, tile height, eye width, eye height) of the eye images."""
    rig = manifest["rig"]
    eye_width, eye_height = rig["eye_projection"]["eye_pixels"]
    tiles = rig.get("settings", {}).get("tiles", [1, 1])
    if not (isinstance(tiles, list) and len(tiles) == 2 and all(isinstance(n, int) and n > 0 for n in tiles)):
        raise InputError(f"{manifest_path}: rig.settings.tiles is not [columns, rows]")
    columns, rows = tiles
    if eye_width % columns or eye_height % rows:
        raise InputError(
            f"{manifest_path}: {eye_width}x{eye_height} eye pixels do not split into {columns}x{rows} tiles"
        )
    return columns, rows, eye_width // columns, eye_height // rows, eye_width, eye_height


def colour_bytes(text, manifest_path):
    digits = text.lstrip("#") if isinstance(text, str) else ""
    if len(digits) != 6:
        raise InputError(f"{manifest_path}: background '{text}' is not #RRGGBB")
    try:
        return tuple(int(digits[index:index + 2], 16) for index in (0, 2, 4))
    except ValueError:
        raise InputError(f"{manifest_path}: background '{text}' is not #RRGGBB")


def srgb_decoded(byte):
    """The linear value Blender's sRGB colour space turns an 8-bit value into."""
    value = byte / 255.0
    return value / 12.92 if value <= 0.04045 else ((value + 0.055) / 1.055) ** 2.4


# ---------------------------------------------------------------- the Blender scene


def world_to_blender(point):
    """ufcsr world (x east, y north, z up) as Blender imports it through glTF: turned -90° about Z."""
    from mathutils import Vector

    return Vector((point[1], -point[0], point[2]))


def import_gltf(path):
    """The objects the glTF importer creates for `path`."""
    import bpy

    before = set(bpy.data.objects)
    result = bpy.ops.import_scene.gltf(filepath=path)
    if "FINISHED" not in result:
        raise InputError(f"{path}: Blender's glTF importer failed")
    return [obj for obj in bpy.data.objects if obj not in before]


def emission_material(name, colour=None, image=None):
    """An unlit material: Emission of `colour` (linear RGB), or of `image` sampled 'Closest'."""
    import bpy

    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.clear()
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = 1.0
    output = nodes.new("ShaderNodeOutputMaterial")
    material.node_tree.links.new(emission.outputs["Emission"], output.inputs["Surface"])
    if image is None:
        emission.inputs["Color"].default_value = (*colour, 1.0)
    else:
        texture = nodes.new("ShaderNodeTexImage")
        texture.image = image
        texture.interpolation = "Closest"
        texture.extension = "EXTEND"
        material.node_tree.links.new(texture.outputs["Color"], emission.inputs["Color"])
    return material


def palette_image(objects, vehicle_path):
    """The palette image vehicle.glb embeds (the capture's), as an sRGB image."""
    for obj in objects:
        for slot in getattr(obj, "material_slots", []):
            if slot.material and slot.material.use_nodes:
                for node in slot.material.node_tree.nodes:
                    if node.type == "TEX_IMAGE" and node.image is not None:
                        node.image.colorspace_settings.name = "sRGB"
                        return node.image
    raise InputError(f"{vehicle_path}: no palette texture on the vehicle's material")


def set_up_vehicle(vehicle_path):
    """vehicle.glb's parts under one empty, each with the palette as Emission, sampled 'Closest'."""
    import bpy

    objects = import_gltf(vehicle_path)
    meshes = [obj for obj in objects if obj.type == "MESH"]
    if not meshes:
        raise InputError(f"{vehicle_path}: no mesh")
    material = emission_material("ufcsr palette", image=palette_image(meshes, vehicle_path))
    for obj in meshes:
        obj.data.materials.clear()
        obj.data.materials.append(material)
    vehicle = bpy.data.objects.new("ufcsr vehicle", None)
    bpy.context.scene.collection.objects.link(vehicle)
    for obj in objects:
        if obj.parent is None:
            obj.parent = vehicle
    return vehicle


def set_up_occluders(scene_path, background_linear):
    """scene.glb's occluders, drawn in the background colour as the capture draws them."""
    material = emission_material("ufcsr occluder", colour=background_linear)
    for obj in import_gltf(scene_path):
        if obj.type == "MESH":
            obj.data.materials.clear()
            obj.data.materials.append(material)


def set_up_colour_and_world(background_linear):
    """Colour management that leaves the palette's bytes unchanged, and the background world."""
    import bpy

    scene = bpy.context.scene
    scene.display_settings.display_device = "sRGB"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.view_settings.use_curve_mapping = False
    scene.sequencer_colorspace_settings.name = "sRGB"
    scene.render.dither_intensity = 0.0
    world = bpy.data.worlds.new("ufcsr background")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (*background_linear, 1.0)
    background.inputs["Strength"].default_value = 1.0
    scene.world = world


def set_up_engine(engine):
    """EEVEE 1 sample, filter 0; or Cycles 1 sample, box filter 0.01, no denoising."""
    import bpy

    scene = bpy.context.scene
    render = scene.render
    if engine == "cycles":
        render.engine = "CYCLES"
        scene.cycles.device = "CPU"
        scene.cycles.samples = 1
        scene.cycles.use_adaptive_sampling = False
        scene.cycles.use_denoising = False
        scene.cycles.pixel_filter_type = "BOX"
        scene.cycles.filter_width = 0.01
        scene.cycles.seed = 0
    else:
        eevee_names = [item.identifier for item in render.bl_rna.properties["engine"].enum_items]
        render.engine = "BLENDER_EEVEE_NEXT" if "BLENDER_EEVEE_NEXT" in eevee_names else "BLENDER_EEVEE"
        scene.eevee.taa_render_samples = 1
        render.filter_size = 0.0
        # Nothing is lit: shadows, ray tracing and ambient occlusion only cost time.
        scene.eevee.use_shadows = False
        scene.eevee.use_raytracing = False
        scene.eevee.use_gtao = False
    render.use_motion_blur = False
    render.film_transparent = False
    render.use_compositing = False
    render.use_sequencer = False
    render.use_border = False
    render.resolution_percentage = 100
    render.pixel_aspect_x = render.pixel_aspect_y = 1.0
    settings = render.image_settings
    settings.file_format = "PNG"
    settings.color_mode = "RGB"
    settings.color_depth = "8"
    settings.compression = 0


def set_up_camera(projection):
    """One camera with the eyes' lens: rectilinear, horizontal field of view, principal point."""
    import bpy

    width, height = projection["eye_pixels"]
    principal_x, principal_y = projection["principal_point_px"]
    camera = bpy.data.objects.new("ufcsr eye", bpy.data.cameras.new("ufcsr eye"))
    bpy.context.scene.collection.objects.link(camera)
    lens = camera.data
    lens.type = "PERSP"
    lens.sensor_fit = "HORIZONTAL"
    lens.angle_x = math.radians(projection["horizontal_fov_deg"])
    lens.clip_start, lens.clip_end = projection["near_m"], projection["far_m"]
    # Blender's shift is a fraction of the width (horizontal fit); image y runs down, shift_y up.
    lens.shift_x = (width / 2.0 - principal_x) / width
    lens.shift_y = (principal_y - height / 2.0) / width
    scene = bpy.context.scene
    scene.camera = camera
    scene.render.resolution_x, scene.render.resolution_y = width, height
    return camera


def place(vehicle, camera, record, eye):
    """The frame's vehicle pose and the eye's camera: +X right, +Y up, looking along -Z."""
    from mathutils import Matrix

    vehicle.location = world_to_blender(record["vehicle"]["position"])
    vehicle.rotation_euler = (0.0, 0.0, math.radians(record["vehicle"]["yaw_deg"]))
    axes = [world_to_blender(eye[name]) for name in ("right", "up", "forward")]
    rotation = Matrix((axes[0], axes[1], -axes[2])).transposed()
    camera.matrix_world = Matrix.Translation(world_to_blender(eye["position"])) @ rotation.to_4x4()


# ---------------------------------------------------------------- rendering and the tiles


def vehicle_region(camera, vehicle, grid):
    """The tiles the vehicle's bounds touch in the camera's image, as (first column, first row,
    last column, last row); None when a bound lies behind the near plane (render the whole image),
    () when the vehicle is out of view (render nothing: every tile shows background)."""
    import bpy
    from bpy_extras.object_utils import world_to_camera_view
    from mathutils import Vector

    scene = bpy.context.scene
    bpy.context.view_layer.update()
    columns, rows, tile_width, tile_height, width, height = grid
    xs, ys = [], []
    for obj in vehicle.children_recursive:
        if obj.type != "MESH":
            continue
        for corner in obj.bound_box:
            point = world_to_camera_view(scene, camera, obj.matrix_world @ Vector(corner))
            if point.z <= camera.data.clip_start:
                return None
            xs.append(point.x * width)
            ys.append((1.0 - point.y) * height)
    # One pixel of margin: a pixel whose centre the bounds' edge passes still belongs to it.
    left, right = max(0.0, min(xs) - 1.0), min(width - 1.0, max(xs) + 1.0)
    top, bottom = max(0.0, min(ys) - 1.0), min(height - 1.0, max(ys) + 1.0)
    if left > right or top > bottom:
        return ()
    first = (int(left) // tile_width, int(top) // tile_height)
    return (*first, int(right) // tile_width, int(bottom) // tile_height)


def tiles_in(region, grid):
    """How many tiles `vehicle_region`'s answer renders."""
    if region is None:
        return grid[0] * grid[1]
    if region == ():
        return 0
    first_column, first_row, last_column, last_row = region
    return (last_column - first_column + 1) * (last_row - first_row + 1)


def render_eye(path, grid, region, background):
    """Renders the active camera's tiles in `region` (all with None) to `path`; returns the eye
    image's 8-bit RGB rows, top row first, the background outside the region."""
    import bpy
    import numpy

    columns, rows, tile_width, tile_height, width, height = grid
    image_rows = numpy.empty((height, width, 3), dtype=numpy.uint8)
    image_rows[:, :] = background
    if region == ():
        return image_rows
    first_column, first_row, last_column, last_row = region or (0, 0, columns - 1, rows - 1)
    left, right = first_column * tile_width, (last_column + 1) * tile_width
    top, bottom = first_row * tile_height, (last_row + 1) * tile_height
    render = bpy.context.scene.render
    render.use_border = render.use_crop_to_border = True
    # Blender's border is a fraction of the image from the bottom left; a quarter pixel inside
    # each edge lands on the same pixel whether Blender truncates or rounds it.
    render.border_min_x, render.border_max_x = (left + 0.25) / width, (right + 0.25) / width
    render.border_min_y = (height - bottom + 0.25) / height
    render.border_max_y = (height - top + 0.25) / height
    render.filepath = path
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(path)
    # A byte image's `pixels` are its bytes / 255 whatever the colour space; Non-Color keeps it so.
    image.colorspace_settings.name = "Non-Color"
    size = tuple(image.size)
    if size != (right - left, bottom - top):
        raise InputError(f"{path}: Blender rendered {size}, not the region of {right - left}x{bottom - top}")
    values = numpy.empty(size[0] * size[1] * image.channels, dtype=numpy.float32)
    image.pixels.foreach_get(values)
    bpy.data.images.remove(image)
    os.remove(path)
    region_rows = numpy.rint(values.reshape(size[1], size[0], -1)[::-1, :, :3] * 255.0)
    image_rows[top:bottom, left:right] = region_rows.astype(numpy.uint8)
    return image_rows


def write_png(path, rgb):
    """An 8-bit RGB PNG of `rgb` (rows top first), written without Blender's colour management."""
    height, width, _ = rgb.shape
    raw = b"".join(b"\x00" + rgb[row].tobytes() for row in range(height))

    def chunk(kind, data):
        checksum = zlib.crc32(kind + data) & 0xFFFFFFFF
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", checksum)

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
    write_new(path, png + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def tiles_of_eye(rgb, grid, backgrounds, out, record, eye_name):
    """Cuts one eye image into the grid's tiles: a PNG where it shows more than background."""
    import numpy

    columns, rows, tile_width, tile_height, _, _ = grid
    entries = []
    for row in range(rows):
        for column in range(columns):
            top, left = row * tile_height, column * tile_width
            tile = rgb[top:top + tile_height, left:left + tile_width]
            is_background = numpy.zeros(tile.shape[:2], dtype=bool)
            for colour in backgrounds:
                is_background |= numpy.all(tile == numpy.array(colour, dtype=numpy.uint8), axis=2)
            entry = {"frame": record["frame"], "eye": eye_name, "row": row, "col": column}
            if is_background.all():
                entry["empty"] = True
            else:
                name = f"tiles/f{record['frame']:04d}_{eye_name}_r{row}_c{column}.png"
                write_png(os.path.join(out, name), tile)
                entry = {"file": name, **entry}
            for key in ("distance_m", "time_s"):
                if key in record:
                    entry[key] = record[key]
            entries.append(entry)
    return entries


# ---------------------------------------------------------------- the archive


def prepare_out(source, out):
    """A new or empty folder for the new archive: never the source, never a link."""
    if os.path.realpath(out) == os.path.realpath(source):
        raise InputError(f"{out}: --out is the source archive; give a new folder")
    if os.path.islink(out):
        raise InputError(f"{out}: is a link (the new archive is not written through it)")
    if os.path.lexists(out) and (not os.path.isdir(out) or os.listdir(out)):
        raise InputError(f"{out}: exists and is not an empty folder (it is not overwritten)")
    os.makedirs(os.path.join(out, "tiles"), exist_ok=True)


def described_files(source, manifest):
    """The PIdT, legend, vehicle, occluders (and an image palette) the manifest
    names, as {name: resolved path}: each inside the source archive with links
    resolved, a regular file of at most COPIED_FILE_LIMIT bytes. Checked before
    Blender imports the vehicle and occluders (a vehicle.glb that is a FIFO or
    a link to /dev/zero must not hang the importer) and before anything is written."""
    manifest_path = os.path.join(source, "manifest.json")
    names = []
    for key in ("pidt", "parts", "vehicle", "occluders"):
        if not isinstance(manifest.get(key), str):
            raise InputError(f"{manifest_path}: '{key}' does not name a file")
        names.append(manifest[key])
    if isinstance(manifest.get("palette"), str):
        names.append(manifest["palette"])
    found = {}
    for name in names:
        real = inside(source, name, manifest_path)
        size = os.stat(real).st_size
        if size > COPIED_FILE_LIMIT:
            raise InputError(f"{os.path.join(source, name)}: {size:,} bytes, more than the {COPIED_FILE_LIMIT:,} bytes allowed")
        found[name] = real
    return found


def refuse_save_blend(path, source, out):
    """--save-blend FILE: never a link, a device, a FIFO or a folder (Blender renames its
    file over whatever is there), never inside the source archive (its inputs) nor --out."""
    if os.path.islink(path) or (os.path.lexists(path) and not os.path.isfile(path)):
        raise InputError(f"{path}: --save-blend is a link or not a regular file: it is not written over")
    real = os.path.realpath(path)
    for folder, what in ((source, "the source archive"), (out, "--out")):
        root = os.path.realpath(folder)
        if os.path.commonpath([real, root]) == root:
            raise InputError(f"{path}: --save-blend is inside {what} ({folder}): give a file elsewhere")


def copy_described_files(source, out, manifest):
    """The PIdT, legend, vehicle, occluders (and an image palette) beside the new
    tiles: each resolved inside the source archive and read by the same rules."""
    for name, real in described_files(source, manifest).items():
        data = read_regular(real, COPIED_FILE_LIMIT)
        target = os.path.join(out, name)
        os.makedirs(os.path.dirname(target), exist_ok=True)
        write_new(target, data)


def write_new(path, data):
    """Writes a file that must not exist yet (never through a link, never over anything)."""
    descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0), 0o644)
    with os.fdopen(descriptor, "wb") as file:
        file.write(data)


def blender_manifest(manifest, records, rendering, engine):
    """The source manifest with Blender's tiles, the frames rendered and what rendered them;
    `rendering` is (the tile entries, how many of them were rendered)."""
    import bpy

    tiles, rendered = rendering
    result = dict(manifest)
    result["tiles"] = tiles
    result["frames"] = []
    for record in records:
        with_vehicle = {}
        for tile in tiles:
            if tile["frame"] == record["frame"] and "file" in tile:
                with_vehicle[tile["eye"]] = with_vehicle.get(tile["eye"], 0) + 1
        frame = dict(record)
        frame["tiles_with_vehicle"] = {eye: with_vehicle.get(eye, 0) for eye in record["eyes"]}
        result["frames"].append(frame)
    empty = sum(1 for tile in tiles if tile.get("empty"))
    engine_name = "Cycles" if engine == "cycles" else "EEVEE"
    result["capture"] = {
        "tool": f"{TOOL} (Blender {bpy.app.version_string}, {engine_name})",
        "tiles_rendered": rendered,
        "tiles_culled": len(tiles) - rendered,
        "tiles_background_only": empty - (len(tiles) - rendered),
        "pixels_scissored": 0,
        "tiles_hidden": 0,
    }
    result["blender"] = {
        "version": bpy.app.version_string,
        "engine": engine_name,
        "samples": 1,
        "pixel_filter": "box 0.01 px" if engine == "cycles" else "0 px",
        "view_transform": "Standard",
        "source_capture": manifest.get("capture"),
    }
    return result


def selected_records(manifest, spec, manifest_path):
    """The archive's frame records that --frames names; each item must name at least one."""
    records = sorted(manifest["frames"], key=lambda record: record["frame"])
    if spec is None:
        return records
    items = frame_selection(spec)

    def named(record, item):
        first, last, step = item
        return first <= record["frame"] <= last and (record["frame"] - first) % step == 0

    for item in items:
        if not any(named(record, item) for record in records):
            first, last, step = item
            if first == last:
                raise InputError(f"{manifest_path}: frame {first} of --frames is not in the archive")
            raise InputError(f"{manifest_path}: --frames {first}-{last}/{step} names no frame of the archive")
    return [record for record in records if any(named(record, item) for item in items)]


def render_archive(arguments):
    import bpy

    source, out = arguments.source, arguments.out
    manifest_path = os.path.join(source, "manifest.json")
    manifest = read_manifest(source)
    records = selected_records(manifest, arguments.frames, manifest_path)
    grid = tile_grid(manifest, manifest_path)
    listed = manifest.get("background", [DEFAULT_BACKGROUND])
    if not isinstance(listed, list) or not listed:
        raise InputError(f"{manifest_path}: 'background' is not a list of colours")
    backgrounds = [colour_bytes(text, manifest_path) for text in listed]
    background_linear = tuple(srgb_decoded(byte) for byte in backgrounds[0])
    inputs = described_files(source, manifest)
    if arguments.save_blend:
        refuse_save_blend(arguments.save_blend, source, out)
    prepare_out(source, out)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    set_up_colour_and_world(background_linear)
    set_up_engine(arguments.engine)
    vehicle = set_up_vehicle(inputs[manifest["vehicle"]])
    set_up_occluders(inputs[manifest["occluders"]], background_linear)
    camera = set_up_camera(manifest["rig"]["eye_projection"])
    if arguments.save_blend:
        first = records[0]
        place(vehicle, camera, first, next(iter(first["eyes"].values())))
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(arguments.save_blend))
    scratch = os.path.join(os.path.abspath(out), ".render.png")
    tiles, rendered = [], 0
    started = time.monotonic()
    for record in records:
        for eye_name, eye in record["eyes"].items():
            place(vehicle, camera, record, eye)
            region = vehicle_region(camera, vehicle, grid)
            rendered += tiles_in(region, grid)
            rgb = render_eye(scratch, grid, region, backgrounds[0])
            tiles.extend(tiles_of_eye(rgb, grid, backgrounds, out, record, eye_name))
        if not arguments.quiet:
            print(f"{TOOL}: frame {record['frame']} rendered", flush=True)
    copy_described_files(source, out, manifest)
    text = json.dumps(blender_manifest(manifest, records, (tiles, rendered), arguments.engine), indent=2)
    # Written last and whole: an interrupted render leaves no manifest, so no half archive reads as one.
    write_new(os.path.join(out, "manifest.json"), (text + "\n").encode("utf-8"))
    if not arguments.quiet:
        written = sum(1 for tile in tiles if "file" in tile)
        seconds = time.monotonic() - started
        print(f"{TOOL}: {len(records)} frames, {written} tiles written in {seconds:.1f} s -> {out}")


def script_arguments():
    """The arguments after `--` (inside Blender), else all of them (python with bpy)."""
    return sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]


def main():
    arguments = parse_arguments(script_arguments())
    try:
        import bpy  # noqa: F401
    except ImportError:
        print(f"{TOOL}: needs Blender's bpy module (pip install bpy==4.2.0 with Python 3.11, "
              "or run it as blender -b -P ufcsr_blender.py -- ...)", file=sys.stderr)
        return 2
    if arguments.quiet:
        # Blender's importer and renderer print to the process's stdout, not through sys.stdout.
        sys.stdout.flush()
        os.dup2(os.open(os.devnull, os.O_WRONLY), 1)
        # The glTF importer logs every node to stderr through this logger.
        logging.getLogger("glTFImporter").disabled = True
    try:
        render_archive(arguments)
    except InputError as error:
        print(f"{TOOL}: {error}", file=sys.stderr)
        return 2
    except OSError as error:
        # A write refused (a file already there, no space, ...): the message names the file.
        print(f"{TOOL}: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    code = main()
    sys.stdout.flush()
    sys.stderr.flush()
    # Blender may crash while it shuts down after a render; the archive is complete by now.
    os._exit(code)
