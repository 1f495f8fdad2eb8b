#!/usr/bin/env python3
"""The tables of docs/literature.md (issue 42 section 7) from the runs
scripts/literature made: per rig and scenario, ufcsr's top five parts by the
paper's total, peak and average (share of the grand total) beside the
angular area, where the parts the seed paper ranked first stand, and the
windshield's texels; then, per body, every published place scored
(published-locations.csv of `ufcsr placement`).

    scripts/literature-tables.py RUNS      (RUNS: the folder scripts/literature wrote)
"""
import csv
import json
import sys
from pathlib import Path

# The seed paper's scenario A, % of the total (arXiv 2604.11406, as issue 42 quotes it).
PAPER_A = [("hood", 11.30), ("bumper", 9.58), ("windshield", 9.51), ("grill", 7.66), ("front-right door", 6.15)]
# The demo truck's part for each of the paper's names.
OURS = {"hood": "hood", "bumper": "front_bumper", "windshield": "windshield", "grill": "grill",
        "front-right door": "door_front_right"}


def ranks(values):
    """1 + the number of strictly larger values: ties share a rank."""
    return {k: 1 + sum(1 for w in values.values() if w > v) for k, v in values.items()}


def count_tables(root):
    for rig in sorted(p for p in (root / "count").iterdir() if p.is_dir()):
        print(f"\n## {rig.name}: the paper's count (60 px/deg unless the run says otherwise) and the angular area")
        for scenario in sorted(p for p in rig.iterdir() if (p / "results/result.json").is_file()):
            result = json.loads((scenario / "results/result.json").read_text())
            parts = {p["name"]: p for p in result["parts"]}
            area = {m["name"]: m["angular_area_deg2_s"] or 0.0 for m in result["measures"]["parts"]}
            area_total = sum(area.values()) or 1.0
            by = {key: ranks({n: p[key] for n, p in parts.items()}) for key in ("total", "peak", "average")}
            area_rank = ranks(area)
            ppd = result["measures"].get("pixels_per_degree")
            print(f"\n### {rig.name} {scenario.name} ({result['measures']['eye_frames']} eye-frames, {ppd} px/deg)")
            for key in ("total", "peak", "average"):
                top = sorted(parts.values(), key=lambda p: (-p[key], p["name"]))[:5]
                print(f"top-5 by {key}: " + ", ".join(f"{p['name']} {p['share']:.2f} %" for p in top))
            print("| paper's part | paper A % | ufcsr part | share % | rank by total / peak / average "
                  "| angular area deg2 s (% , rank) |")
            for name, paper in PAPER_A:
                ours = OURS[name]
                p = parts.get(ours)
                if p is None:
                    print(f"| {name} | {paper} | (none) | | | |")
                    continue
                print(f"| {name} | {paper:.2f} | {ours} | {p['share']:.2f} | {by['total'][ours]} / "
                      f"{by['peak'][ours]} / {by['average'][ours]} of {len(parts)} | "
                      f"{area.get(ours, 0):.1f} ({100 * area.get(ours, 0) / area_total:.2f} %, "
                      f"{area_rank.get(ours)}) |")
            top_area = sorted(area, key=lambda n: -area[n])[:5]
            print("top-5 by angular area: " + ", ".join(f"{n} {100 * area[n] / area_total:.2f} %" for n in top_area))
            if "windshield" in parts:
                print(f"windshield texels: {parts['windshield']['texels']}")


def place_tables(root):
    print("\n## published places, per body (legible s [95 % over scenarios], visible s, rank)")
    for body in sorted(p for p in (root / "places").iterdir() if (p / "placement/published-locations.csv").is_file()):
        print(f"\n### {body.name}")
        print("| place | best part: legible s [95 %], visible s, rank | best patch: legible s [95 %], visible s, rank |")
        rows = {}
        with open(body / "placement/published-locations.csv", newline="") as f:
            for row in csv.DictReader(f):
                rows.setdefault(row["location"], {})[row["kind"]] = row
        for place, kinds in rows.items():
            cells = []
            for kind in ("part", "patch"):
                r = kinds.get(kind)
                if not r or not r["best"]:
                    cells.append("none")
                    continue
                ci = f" [{float(r['ci95_low_s']):.2f}-{float(r['ci95_high_s']):.2f}]" if r["ci95_low_s"] else ""
                mount = "" if r["mountable"] == "true" else ", not mountable"
                cells.append(f"{r['best']} {float(r['legible_s']):.2f}{ci}, {float(r['visible_s']):.2f}, "
                             f"{r['rank']} of {r['of']}{mount}")
            print(f"| {place} | {cells[0]} | {cells[1]} |")


def main():
    root = Path(sys.argv[1] if len(sys.argv) > 1 else "runs/literature")
    if (root / "count").is_dir():
        count_tables(root)
    if (root / "places").is_dir():
        place_tables(root)


if __name__ == "__main__":
    main()
