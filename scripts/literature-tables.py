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


# The bodies of §2 in the page's order.
BODIES = ["truck", "sedan", "suv", "van", "pickup", "bus"]
RIGS = [("unity-eye-1.159m", "Unity scenarios, Unity eye 1.159 m"), ("unity-eye-1.75m", "Unity scenarios, eye 1.75 m"),
        ("demo-eye-1.75m", "demo A–D, eye 1.75 m")]


def run_ranks(result):
    """Per part of one run: share %, rank by total, peak and average, angular-area share % and rank."""
    parts = {p["name"]: p for p in result["parts"]}
    area = {m["name"]: m["angular_area_deg2_s"] or 0.0 for m in result["measures"]["parts"]}
    area_total = sum(area.values()) or 1.0
    area_share = {n: 100 * a / area_total for n, a in area.items()}
    by = {key: ranks({n: p[key] for n, p in parts.items()}) for key in ("total", "peak", "average")}
    return parts, by, area_share, ranks(area)


def page_table(root):
    """§1's table as docs/literature.md prints it: per paper part and rig, each scenario's rank by
    total (angular-area share, its rank); then the figures its text quotes."""
    runs = {}
    for rig, _ in RIGS:
        for scenario in "ABCD":
            path = root / "count" / rig / scenario / "results/result.json"
            if path.is_file():
                runs[rig, scenario] = run_ranks(json.loads(path.read_text()))
    if not runs:
        return
    print("\n## §1 as the page prints it")
    print("\n| paper's part, scenario A | ufcsr part | " + " | ".join(title for _, title in RIGS) + " |")
    print("| --- | --- | " + " | ".join("---" for _ in RIGS) + " |")
    for name, paper in PAPER_A:
        ours = OURS[name]
        cells = []
        for rig, _ in RIGS:
            cell = []
            for scenario in "ABCD":
                if (rig, scenario) not in runs:
                    continue
                parts, by, share, area_rank = runs[rig, scenario]
                cell.append(f"{scenario} {by['total'][ours]} ({share.get(ours, 0):.1f} %, {area_rank.get(ours)})")
            cells.append("; ".join(cell))
        print(f"| {name} {paper:.2f} % | `{ours}` | " + " | ".join(cells) + " |")
    print("\nper run: hood rank by total / peak / average; rank by total of windshield, grill, bumper, "
          "front-right door; largest |count share - angular-area share| (pp, part)")
    for (rig, scenario), (parts, by, share, _) in runs.items():
        gap = max(parts, key=lambda n: abs(parts[n]["share"] - share.get(n, 0)))
        print(f"{rig} {scenario}: hood {by['total']['hood']}/{by['peak']['hood']}/{by['average']['hood']}; "
              + ", ".join(f"{OURS[n]} {by['total'][OURS[n]]}" for n in ("windshield", "grill", "bumper", "front-right door"))
              + f"; {abs(parts[gap]['share'] - share.get(gap, 0)):.2f} pp ({gap})")


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


def place_cell(r):
    """One candidate as the page prints it: `name` legible s [95 %], visible s, rank/of."""
    if not r or not r["best"]:
        return "none"
    name = r["best"].replace("@0.40x0.15@", "@…")
    ci = f" [{float(r['ci95_low_s']):.2f}–{float(r['ci95_high_s']):.2f}]" if r["ci95_low_s"] else ""
    mount = "" if r["mountable"] == "true" else ", not mountable"
    return f"`{name}` {float(r['legible_s']):.2f}{ci}, {float(r['visible_s']):.2f}, {r['rank']}/{r['of']}{mount}"


def place_tables(root):
    """§2's tables as docs/literature.md prints them, one per body (published-locations.csv)."""
    print("\n## §2 as the page prints it: published places per body (legible s [95 % over scenarios], visible s, rank)")
    bodies = {p.name: p for p in (root / "places").iterdir() if (p / "placement/published-locations.csv").is_file()}
    titles = {"truck": "demo truck", "pickup": "pickup (family)"}
    for body in BODIES + sorted(set(bodies) - set(BODIES)):
        if body not in bodies:
            continue
        print(f"\n**{titles.get(body, body)}**\n")
        print("| place | best part: legible s [95 %], visible s, rank/of | best patch: legible s [95 %], visible s, rank/of |")
        print("| --- | --- | --- |")
        rows = {}
        with open(bodies[body] / "placement/published-locations.csv", newline="") as f:
            for row in csv.DictReader(f):
                rows.setdefault(row["location"], {})[row["kind"]] = row
        for place, kinds in rows.items():
            label = "front fenders" if place.startswith("above the front wheels") else place
            print(f"| {label} | {place_cell(kinds.get('part'))} | {place_cell(kinds.get('patch'))} |")



def main():
    root = Path(sys.argv[1] if len(sys.argv) > 1 else "runs/literature")
    if (root / "count").is_dir():
        count_tables(root)
        page_table(root)
    if (root / "places").is_dir():
        place_tables(root)


if __name__ == "__main__":
    main()
