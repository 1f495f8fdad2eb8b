#!/usr/bin/env python3
"""Writes fixtures/scenes/box-truck.{obj,mtl,gltf}: a small box truck used to test
bringing your own vehicle to ufcsr-capture. Y up, +Z forward (the glTF
convention), metres; every face is its own OBJ object / glTF material with its
own UV cell, so the mesh also exercises --keep-uvs."""
import base64
import json
import os
import struct

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "fixtures", "scenes")
BOXES = [
    ("cargo", (-1.1, 0.4, -3.0), (1.1, 3.2, 1.2)),
    ("cab", (-1.05, 0.4, 1.2), (1.05, 2.6, 3.0)),
]
FACES = {"right": (0, -1), "left": (0, 1), "bottom": (1, -1), "top": (1, 1), "rear": (2, -1), "front": (2, 1)}
CELLS = 4


def face_quad(lo, hi, axis, sign):
    """Corners of a box face, counter-clockwise seen from outside."""
    fixed = hi[axis] if sign > 0 else lo[axis]
    u_ax, v_ax = [(1, 2), (2, 0), (0, 1)][axis]
    pts = []
    for du, dv in [(0, 0), (1, 0), (1, 1), (0, 1)]:
        p = [0, 0, 0]
        p[axis] = fixed
        p[u_ax] = hi[u_ax] if du else lo[u_ax]
        p[v_ax] = hi[v_ax] if dv else lo[v_ax]
        pts.append(p)
    if sign < 0:
        pts = [pts[0], pts[3], pts[2], pts[1]]
    return pts


def uv_of(i, corner):
    """UV of a face corner: face i in its own grid cell, v = 0 at the top."""
    cx, cy = i % CELLS, i // CELLS
    m = 0.05
    u = (cx + m + (1 - 2 * m) * (corner in (1, 2))) / CELLS
    v = (cy + m + (1 - 2 * m) * (corner in (2, 3))) / CELLS
    return u, v


quads = []
for bname, lo, hi in BOXES:
    for fname, (axis, sign) in FACES.items():
        if fname == "bottom" or (bname == "cab" and fname == "rear"):
            continue
        quads.append((f"{bname}_{fname}", face_quad(lo, hi, axis, sign)))

# OBJ puts v = 0 at the bottom of the texture, so flip.
with open(os.path.join(OUT, "box-truck.obj"), "w") as f:
    f.write("# Box truck for ufcsr-capture tests: Y up, +Z forward, metres; one group and material per face\n")
    f.write("mtllib box-truck.mtl\n")
    vi = 1
    for i, (name, pts) in enumerate(quads):
        f.write(f"o {name}\nusemtl mat_{name}\n")
        for p in pts:
            f.write("v %.3f %.3f %.3f\n" % tuple(p))
        for c in range(4):
            u, v = uv_of(i, c)
            f.write("vt %.5f %.5f\n" % (u, 1 - v))
        f.write(f"f {vi}/{vi} {vi+1}/{vi+1} {vi+2}/{vi+2} {vi+3}/{vi+3}\n")
        vi += 4
with open(os.path.join(OUT, "box-truck.mtl"), "w") as f:
    for name, _ in quads:
        f.write(f"newmtl mat_{name}\nKd 0.8 0.8 0.8\n\n")

# glTF with an embedded buffer: one node per box, one primitive (and material) per face.
pos, uvs, idx = bytearray(), bytearray(), bytearray()
accessors, materials, prims_by_box = [], [], {}
for i, (name, pts) in enumerate(quads):
    box = name.split("_")[0]
    base_pos, base_uv, base_idx = len(pos), len(uvs), len(idx)
    for p in pts:
        pos += struct.pack("<3f", *p)
    for c in range(4):
        uvs += struct.pack("<2f", *uv_of(i, c))
    for k in (0, 1, 2, 0, 2, 3):
        idx += struct.pack("<H", k)
    lo = [min(p[a] for p in pts) for a in range(3)]
    hi = [max(p[a] for p in pts) for a in range(3)]
    a0 = len(accessors)
    accessors += [
        {"bufferView": 0, "byteOffset": base_pos, "componentType": 5126, "count": 4, "type": "VEC3", "min": lo, "max": hi},
        {"bufferView": 1, "byteOffset": base_uv, "componentType": 5126, "count": 4, "type": "VEC2"},
        {"bufferView": 2, "byteOffset": base_idx, "componentType": 5123, "count": 6, "type": "SCALAR"},
    ]
    materials.append({"name": name})
    prims_by_box.setdefault(box, []).append(
        {"attributes": {"POSITION": a0, "TEXCOORD_0": a0 + 1}, "indices": a0 + 2, "material": len(materials) - 1}
    )
while len(idx) % 4:
    idx += b"\0"
buf = bytes(pos) + bytes(uvs) + bytes(idx)
views = [
    {"buffer": 0, "byteOffset": 0, "byteLength": len(pos)},
    {"buffer": 0, "byteOffset": len(pos), "byteLength": len(uvs)},
    {"buffer": 0, "byteOffset": len(pos) + len(uvs), "byteLength": len(idx)},
]
meshes, nodes = [], []
for box, prims in prims_by_box.items():
    meshes.append({"name": f"{box}_mesh", "primitives": prims})
    nodes.append({"name": box, "mesh": len(meshes) - 1})
gltf = {
    "asset": {"version": "2.0", "generator": "ufcsr scripts/capture-make-box-truck.py"},
    "scene": 0,
    "scenes": [{"nodes": list(range(len(nodes)))}],
    "nodes": nodes,
    "meshes": meshes,
    "materials": materials,
    "accessors": accessors,
    "bufferViews": views,
    "buffers": [{"byteLength": len(buf), "uri": "data:application/octet-stream;base64," + base64.b64encode(buf).decode()}],
}
with open(os.path.join(OUT, "box-truck.gltf"), "w") as f:
    json.dump(gltf, f, indent=1)
print(f"wrote {len(quads)} faces to {OUT}/box-truck.{{obj,mtl,gltf}}")

# The same truck as binary glTF (.glb): JSON chunk + BIN chunk, no data URI.
glb_json = dict(gltf)
glb_json["buffers"] = [{"byteLength": len(buf)}]
json_bytes = json.dumps(glb_json, separators=(",", ":")).encode()
json_bytes += b" " * (-len(json_bytes) % 4)
bin_bytes = buf + b"\0" * (-len(buf) % 4)
total = 12 + 8 + len(json_bytes) + 8 + len(bin_bytes)
with open(os.path.join(OUT, "box-truck.glb"), "wb") as f:
    f.write(struct.pack("<4sII", b"glTF", 2, total))
    f.write(struct.pack("<I4s", len(json_bytes), b"JSON") + json_bytes)
    f.write(struct.pack("<I4s", len(bin_bytes), b"BIN\0") + bin_bytes)
print(f"wrote {OUT}/box-truck.glb")
