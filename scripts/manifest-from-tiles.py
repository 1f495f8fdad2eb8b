#!/usr/bin/env python3
"""Write manifest.json for a folder of tiles rendered by Unity or Blender.

ufcsr-analyze reads any folder of PNG tiles, but with a manifest it also knows
which tiles form one eye-frame (for --dedupe frame) and which palette, PIdT,
legend and background the capture used, so `ufcsr-analyze ARCHIVE` needs no
options. The frame, eye, row and column of each tile come from its file name,
matched by a regular expression with named groups.

  scripts/manifest-from-tiles.py ARCHIVE [--pattern REGEX] [--palette 4096x4096|palette.png]
                                 [--pidt pidt.png] [--parts parts.csv] [--background '#000FFF' ...]

The default pattern matches ufcsr-capture's names, e.g. tiles/f0012_left_r2_c3.png;
for Unity-style names such as Left_0012_2_3.png use
  --pattern '(?P<eye>Left|Right)_(?P<frame>\\d+)_(?P<row>\\d+)_(?P<col>\\d+)\\.png$'
Paths given for --palette/--pidt/--parts must lie inside ARCHIVE.
Only the Python standard library is needed.
"""

import argparse
import json
import os
import re
import sys

DEFAULT_PATTERN = r"f(?P<frame>\d+)_(?P<eye>[A-Za-z0-9]+)_r(?P<row>\d+)_c(?P<col>\d+)\.png$"


def fail(message):
    print(f"error: {message}", file=sys.stderr)
    sys.exit(2)


def relative_inside(archive, path, what):
    full = os.path.abspath(path if os.path.isabs(path) else os.path.join(archive, path))
    relative = os.path.relpath(full, archive)
    if relative.startswith(".."):
        fail(f"{what} {path} must be inside the archive folder {archive}")
    if not os.path.isfile(full):
        fail(f"{what} {path}: no such file")
    return relative.replace(os.sep, "/")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("archive")
    parser.add_argument("--pattern", default=DEFAULT_PATTERN)
    parser.add_argument("--palette", help="WxH of the canonical palette, or a palette PNG inside the archive")
    parser.add_argument("--pidt")
    parser.add_argument("--parts")
    parser.add_argument("--background", action="append")
    args = parser.parse_args()

    archive = os.path.abspath(args.archive)
    if not os.path.isdir(archive):
        fail(f"{args.archive}: not a folder")
    try:
        pattern = re.compile(args.pattern)
    except re.error as error:
        fail(f"invalid --pattern: {error}")
    missing = {"frame", "eye", "row", "col"} - set(pattern.groupindex)
    if missing:
        fail(f"--pattern needs the named groups frame, eye, row and col (missing: {', '.join(sorted(missing))})")

    excluded = {relative_inside(archive, p, "file") for p in (args.pidt, args.palette) if p and "x" not in p}
    tiles, unmatched = [], []
    for folder, _, files in os.walk(archive):
        for name in sorted(files):
            if not name.lower().endswith(".png"):
                continue
            relative = os.path.relpath(os.path.join(folder, name), archive).replace(os.sep, "/")
            if relative in excluded:
                continue
            match = pattern.search(relative)
            if not match:
                unmatched.append(relative)
                continue
            tiles.append({
                "file": relative,
                "frame": int(match["frame"]),
                "eye": match["eye"].lower(),
                "row": int(match["row"]),
                "col": int(match["col"]),
            })
    if unmatched:
        fail(f"{len(unmatched)} PNG files do not match --pattern, e.g. {unmatched[0]} (nothing written)")
    if not tiles:
        fail(f"no PNG tiles found in {args.archive}")
    tiles.sort(key=lambda t: (t["frame"], t["eye"], t["row"], t["col"]))
    seen = set()
    for tile in tiles:
        key = (tile["frame"], tile["eye"], tile["row"], tile["col"])
        if key in seen:
            fail(f"two files are frame {key[0]}, eye {key[1]}, row {key[2]}, col {key[3]}: e.g. {tile['file']}")
        seen.add(key)

    manifest = {"schema": "ufcsr-manifest/1"}
    if args.palette:
        size = re.fullmatch(r"(\d+)[xX](\d+)", args.palette)
        manifest["palette"] = (
            {"canonical": [int(size[1]), int(size[2])]} if size else relative_inside(archive, args.palette, "--palette")
        )
    if args.pidt:
        manifest["pidt"] = relative_inside(archive, args.pidt, "--pidt")
    if args.parts:
        manifest["parts"] = relative_inside(archive, args.parts, "--parts")
    if args.background:
        for color in args.background:
            if not re.fullmatch(r"#?[0-9A-Fa-f]{6}", color):
                fail(f"invalid --background {color!r}: expected #RRGGBB")
        manifest["background"] = ["#" + c.lstrip("#").upper() for c in args.background]
    manifest["tiles"] = tiles
    manifest["generator"] = "scripts/manifest-from-tiles.py"

    target = os.path.join(archive, "manifest.json")
    temporary = target + ".tmp"
    with open(temporary, "w") as out:
        json.dump(manifest, out, indent=1)
        out.write("\n")
    os.replace(temporary, target)
    frames = len({(t["frame"], t["eye"]) for t in tiles})
    print(f"wrote {target}: {len(tiles)} tiles in {frames} eye-frames")


if __name__ == "__main__":
    main()
