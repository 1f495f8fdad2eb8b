#!/usr/bin/env python3
"""How three rules for keeping every Nth frame sample a scenario's time integral
(docs/science.md, "Every Nth frame"), from the study folders `scripts/study-demo OUT`
writes: per scenario and step, the share L1 (pp) of the angular area summed over
the kept frames against every frame, using the finest setting's `frames.csv`
(40 px/°, every frame) as the truth.

    scripts/frame-step-rules.py OUT [STEPS...]      (default steps: 3 10 30)

Rules: `first` keeps frames 0, N, ... up to the last (the first rule); `starts`
keeps them only while more than half of the N frames after each lie in the
scenario (the second); `middles` keeps the middle frame of each block of N frames
lying mostly in the scenario (ufcsr's `stepped_frames` since 2026-12-06). Every
rule weighs its frames alike, so the shares depend only on which frames it keeps.
The range is over the step's offsets (the grid moved by 0 ... N-1 frames).
"""
import collections
import csv
import sys
from pathlib import Path


def per_frame(path):
    values = collections.defaultdict(lambda: collections.defaultdict(float))
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            values[int(row["frame"])][row["part"]] += float(row["solid_angle_sr"])
    return values


def shares(frames, values):
    total = collections.defaultdict(float)
    for frame in frames:
        for part, v in values[frame].items():
            total[part] += v
    whole = sum(total.values()) or 1.0
    return {part: 100.0 * v / whole for part, v in total.items()}


def l1(a, b):
    return sum(abs(a.get(p, 0.0) - b.get(p, 0.0)) for p in set(a) | set(b))


def first(n, step, phase):
    return list(range(phase, n, step))


def starts(n, step, phase):
    kept = [f for f in range(phase, n, step) if 2 * f + step < 2 * n]
    return kept or [phase]


def middles(n, step, phase):
    half = step // 2
    inside = lambda f: max(0, min(f - half + step, n) - max(f - half, 0))
    kept = [f for f in range(phase, n, step) if 2 * inside(f) > step]
    return kept or [min(phase, (n - 1) // 2)]


def main():
    out = Path(sys.argv[1])
    steps = [int(s) for s in sys.argv[2:]] or [3, 10, 30]
    rules = [("first", first, lambda s: 0), ("starts", starts, lambda s: 0), ("middles", middles, lambda s: s // 2)]
    print("| scenario, step | " + " | ".join(name for name, _, _ in rules) + " | range over offsets (" +
          ", ".join(name for name, _, _ in rules) + ") |")
    print("| --- " * (len(rules) + 2) + "|")
    for study in sorted(p for p in out.iterdir() if (p / "ppd40-step1/results/frames.csv").is_file()):
        values = per_frame(study / "ppd40-step1/results/frames.csv")
        n = max(values) + 1
        truth = shares(range(n), values)
        for step in steps:
            points, ranges = [], []
            for _, rule, phase in rules:
                errors = [l1(truth, shares(rule(n, step, o), values)) for o in range(min(step, n))]
                points.append(f"{l1(truth, shares(rule(n, step, phase(step)), values)):.2f}")
                ranges.append(f"{min(errors):.2f}–{max(errors):.2f}")
            print(f"| {study.name}, {step} | " + " | ".join(points) + " | " + "; ".join(ranges) + " |")


if __name__ == "__main__":
    main()
