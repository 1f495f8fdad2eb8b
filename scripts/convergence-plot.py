#!/usr/bin/env python3
"""The convergence table and figure from `scripts/convergence`'s study folders.

For every OUT/<scenario>-<measure>/study.json it takes each setting's
resolution error: its share L1 against the exact counterpart on the same
eye-frames (`error_vs_exact.resolution_pp`: every texel of those frames, so
no sampling error; the frame step's own error, against every frame, is the
study's `share_l1_pp` and is not what converges in ppd) over pixels per
degree, fits error ≈ c · ppd^rate by least squares on log–log (every point),
prints a Markdown table, and, when matplotlib is installed, draws one panel
per measure with a line per scenario.

    scripts/convergence-plot.py OUT [FIGURE.png]
"""
import json
import math
import sys
from pathlib import Path


def error_of(row):
    exact = row.get("error_vs_exact") or {}
    return exact.get("resolution_pp"), None


def curves(out):
    found = {}
    for study_file in sorted(Path(out).glob("*-*/study.json")):
        scenario, measure = study_file.parent.name.split("-", 1)
        study = json.loads(study_file.read_text())
        points = []
        for row in study["rows"]:
            error, ci = error_of(row)
            if error is not None:
                points.append((row["ppd"], error, ci, row["seconds"]))
        exact = study.get("exact") or {}
        found[(measure, scenario)] = (sorted(points), exact.get("seconds"))
    return found


def fitted_rate(points):
    xs = [math.log(p) for p, e, _, _ in points if e > 0]
    ys = [math.log(e) for p, e, _, _ in points if e > 0]
    if len(xs) < 2:
        return float("nan")
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx if sxx else float("nan")


def table(found):
    ppds = sorted({p for points, _ in found.values() for p, *_ in points})
    head = "| measure | scenario | " + " | ".join(f"{p:g} px/°" for p in ppds)
    print(head + " | fitted rate | exact reference (s) |")
    print("|" + " --- |" * (len(ppds) + 4))
    for (measure, scenario), (points, exact_seconds) in sorted(found.items()):
        by_ppd = {p: e for p, e, _, _ in points}
        cells = [f"{by_ppd[p]:.2f}" if p in by_ppd else "" for p in ppds]
        rate = fitted_rate(points)
        seconds = f"{exact_seconds:.0f}" if exact_seconds is not None else ""
        print(f"| {measure} | {scenario} | " + " | ".join(cells) + f" | ppd^{rate:.2f} | {seconds} |")


def figure(found, path):
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("convergence-plot: no matplotlib, no figure (pip install matplotlib)", file=sys.stderr)
        return
    measures = sorted({m for m, _ in found})
    fig, axes = plt.subplots(1, len(measures), figsize=(5.2 * len(measures), 4.2), squeeze=False)
    titles = {
        "angular-area": "visible angular area vs ray-traced solid angle",
        "count": "paper's count vs any-part visibility",
    }
    for axis, measure in zip(axes[0], measures):
        for (m, scenario), (points, _) in sorted(found.items()):
            if m != measure or not points:
                continue
            ppd = [p for p, *_ in points]
            error = [e for _, e, _, _ in points]
            rate = fitted_rate(points)
            axis.plot(ppd, error, marker="o", label=f"scenario {scenario} (∝ ppd^{rate:.2f})")
        axis.set_xscale("log")
        axis.set_yscale("log")
        # Plain numbers at the measured ppds and at 1-2-3-5 steps of the error, not 10^x labels.
        from matplotlib.ticker import FixedLocator, FuncFormatter, NullFormatter
        ppds = sorted({p for (m, _), (points, _) in found.items() if m == measure for p, *_ in points})
        axis.xaxis.set_major_locator(FixedLocator(ppds))
        axis.xaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        axis.xaxis.set_minor_formatter(NullFormatter())
        decades = [d * 10.0 ** k for k in range(-3, 4) for d in (1, 2, 3, 5)]
        axis.yaxis.set_major_locator(FixedLocator(decades))
        axis.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        axis.yaxis.set_minor_formatter(NullFormatter())
        axis.set_xlabel("pixels per degree")
        axis.set_ylabel("share L1 against the exact counterpart, same frames (pp)")
        axis.set_title(titles.get(measure, measure), fontsize=10)
        axis.grid(True, which="major", alpha=0.3)
        axis.legend(fontsize=8, loc="best")
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    print(f"convergence-plot: wrote {path}", file=sys.stderr)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    found = curves(sys.argv[1])
    if not found:
        sys.exit(f"convergence-plot: no */study.json under {sys.argv[1]}")
    table(found)
    if len(sys.argv) > 2:
        figure(found, sys.argv[2])


if __name__ == "__main__":
    main()
