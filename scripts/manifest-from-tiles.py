#!/usr/bin/env python3
"""Deprecated: use `ufcsr manifest` (this script now calls it).

Writes manifest.json for a folder of frames rendered by Unity or Blender, so
that `ufcsr analyze ARCHIVE` needs no options. Everything is done by the
subcommand `ufcsr manifest`, which also describes untiled captures
(one image per eye and frame), takes the fps, field of view or pixels per
degree, a rig file and frame times, and checks tile sizes and grids; see
`ufcsr manifest --help` and docs/guide.md#unity-and-blender-captures.

  scripts/manifest-from-tiles.py ARCHIVE [--pattern REGEX] [--palette 4096x4096|palette.png]
                                 [--pidt pidt.png] [--parts parts.csv] [--background '#000FFF' ...]
                                 [any other option of ufcsr manifest, e.g. --fps 60 --fov 107]

--palette WxH becomes --palette-size WxH, --palette FILE becomes --fcsp FILE; everything
else is passed on unchanged. Paths are relative to the working directory (before, --pidt,
--palette and --parts were taken relative to ARCHIVE). The binary is $UFCSR_ANALYZE, else
`ufcsr-analyze` on PATH. Only the Python standard library is needed.
"""

import argparse
import os
import re
import shutil
import subprocess
import sys


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], add_help=True)
    parser.add_argument("archive")
    parser.add_argument("--palette", help="WxH of the canonical palette, or a palette PNG")
    args, rest = parser.parse_known_args()
    binary = os.environ.get("UFCSR_ANALYZE") or shutil.which("ufcsr-analyze")
    if not binary:
        print("error: ufcsr-analyze not found: put it on PATH or set UFCSR_ANALYZE to its path "
              "(this script only calls `ufcsr manifest`)", file=sys.stderr)
        return 2
    command = [binary, "manifest", args.archive]
    if args.palette:
        is_size = re.fullmatch(r"\d+([xX]\d+)?", args.palette)
        command += ["--palette-size" if is_size else "--fcsp", args.palette]
    print("note: scripts/manifest-from-tiles.py is deprecated; it runs: "
          + " ".join(command[1:] + rest), file=sys.stderr)
    return subprocess.call(command + rest)


if __name__ == "__main__":
    sys.exit(main())
