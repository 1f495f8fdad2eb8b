"""A ufcsr result set read back into pandas and numpy.

Its own module so that reading results (``read_result``) needs nothing of the
analysis options: a result folder written by ``ufcsr-analyze`` on a cluster
reads the same as one written by ``ufcsr.analyze`` in a notebook.
"""

from __future__ import annotations

import json
import os
from functools import cached_property
from pathlib import Path
from typing import Any, Optional, Union

import numpy as np
import pandas as pd

from . import _native

PathLike = Union[str, "os.PathLike[str]"]

RESULT_FILE = "result.json"
FRAMES_FILE = "frames.csv"

# result.json's per-part fields, in the report's order (PartStats).
PART_COLUMNS = ["name", "color", "texels", "total", "peak", "average", "share", "coverage", "texels_seen"]
# result.json's measures.parts fields joined onto the parts (when frames were tallied).
MEASURE_COLUMNS = ["pixels", "eye_frames_seen", "angular_area_deg2_s", "exposure_s"]


def result_json_path(path: PathLike) -> Path:
    """The result.json that ``path`` (the file or its folder) names."""
    path = Path(os.fspath(path))
    return path / RESULT_FILE if path.is_dir() else path


def _parts_frame(summary: dict[str, Any]) -> pd.DataFrame:
    """One row per legend part, the report's columns, plus the measures when present."""
    parts = pd.DataFrame(summary.get("parts", []), columns=PART_COLUMNS)
    measures = (summary.get("measures") or {}).get("parts") or []
    # The measures list the legend's parts in legend order, then "(unlabelled)".
    names = [measure["name"] for measure in measures[: len(parts)]]
    if measures and names == list(parts["name"]):
        for column in MEASURE_COLUMNS:
            parts[column] = [measure.get(column) for measure in measures[: len(parts)]]
    return parts


class Result:
    """One analysis result: ``result.json`` and ``frames.csv`` of a results folder.

    Attributes:
        path: the result.json read.
        parts: pandas DataFrame, one row per legend part (name, color, texels,
            total, peak, average, share %, coverage %, texels_seen, and with
            frames tallied pixels, eye_frames_seen, angular_area_deg2_s,
            exposure_s).
        frames: frames.csv as a DataFrame (one row per eye-frame and part), or
            None when the analysis wrote none.
        texel_counts: numpy uint32 array of the palette's size, the count per
            texel index (``y * width + x``), decoded in Rust on first use.
        summary: the rest of result.json as a dict (images, settings,
            warnings, measures, ...).
    """

    def __init__(self, path: PathLike):
        self.path = result_json_path(path)
        summary = json.loads(_native.read_summary_json(os.fspath(self.path)))
        self.parts = _parts_frame(summary)
        summary.pop("parts", None)
        self.summary: dict[str, Any] = summary
        frames = self.path.parent / FRAMES_FILE
        self.frames: Optional[pd.DataFrame] = pd.read_csv(frames) if frames.is_file() else None

    @cached_property
    def texel_counts(self) -> np.ndarray:
        counts, width, height = _native.read_texel_counts(os.fspath(self.path))
        # The bytearray becomes the array's memory: no per-element copy.
        return np.frombuffer(counts, dtype="<u4").astype(np.uint32, copy=False)

    @property
    def palette_size(self) -> tuple[int, int]:
        """(width, height) of the palette the texel indices address."""
        palette = self.summary["settings"]["palette"]
        return palette["width"], palette["height"]

    @property
    def grand_total(self) -> int:
        """Sum of the part totals over legend parts (without a PIdT: over all texels)."""
        return self.summary["grand_total"]

    @property
    def complete(self) -> bool:
        """True when every image was read (``ufcsr-analyze``'s exit status 0)."""
        return self.summary["images"]["failed"] == 0

    def __repr__(self) -> str:
        images = self.summary["images"]
        width, height = self.palette_size
        frames = "no frames.csv" if self.frames is None else f"frames.csv {len(self.frames):,} rows"
        return (
            f"<ufcsr.Result of {self.summary['settings']['archive']!r}: {len(self.parts)} parts, "
            f"grand total {self.grand_total:,} (measure {self.summary.get('measure', 'pixels')!r}), "
            f"{images['found']:,} images ({images['failed']} failed), palette {width}×{height}, "
            f"{frames}; read from {os.fspath(self.path)!r}>"
        )


def read_result(path: PathLike) -> Result:
    """Reads a result set: ``path`` is a ``result.json`` or the folder holding it.

    Raises ``ufcsr.UfcsrError`` (naming the file) when it is missing or not a
    ufcsr result.
    """
    return Result(path)
