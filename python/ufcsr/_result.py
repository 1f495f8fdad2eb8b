"""A ufcsr result set read back into pandas and numpy, in pure Python.

Its own module so that reading results (``read_result``) needs nothing of the
analysis: a result folder written by ``ufcsr-analyze`` on a cluster reads the
same as one written by ``ufcsr.analyze`` in a notebook. The per-texel counts
are decoded from result.json's delta encoding with numpy, checked as the
analyzer checks them (src/result/result_json.rs), so an edited or truncated
file is an error naming it, never silently different counts.
"""

from __future__ import annotations

import os
from functools import cached_property
from pathlib import Path
from typing import Any, Optional

import numpy as np
import pandas as pd

from ._files import (
    PathLike,
    UfcsrError,
    count,
    field,
    number,
    parse_json,
    read_bytes,
    read_table,
    refuse_half_written,
)

RESULT_FILE = "result.json"
FRAMES_FILE = "frames.csv"
TEXEL_AREA_FILE = "texel-area.f32"
TEXEL_AREA_MAGIC = b"ufcsr-texel-area/1\n\0"
RESULT_SCHEMA = "ufcsr-result/1"

# result.json's per-part fields, in the report's order (PartStats).
PART_FIELDS = ["name", "color", "texels", "total", "peak", "average", "share", "coverage", "texels_seen"]
# The DataFrame's columns: parts.csv's names, the unit in the name (share and coverage in %).
PART_COLUMNS = ["name", "color", "texels", "total", "peak", "average", "share_percent", "coverage_percent", "texels_seen"]
# The per-part fields that count something: whole numbers of at least 0.
PART_COUNTS = ["texels", "total", "peak", "texels_seen"]
# result.json's measures.parts fields joined onto the parts (when frames were tallied).
MEASURE_COLUMNS = ["pixels", "eye_frames_seen", "angular_area_deg2_s", "exposure_s"]
# The largest palette: 2^26 texels with 32-bit texel ids (ufcsr::MAX_RGBA32_TEXELS);
# archives of 24-bit colours hold at most 2^24.
MAX_TEXELS = 1 << 26


def result_json_path(path: PathLike) -> Path:
    """The result.json that ``path`` (the file or its folder) names."""
    path = Path(os.fspath(path))
    return path / RESULT_FILE if path.is_dir() else path


def _document(path: Path) -> dict[str, Any]:
    """result.json parsed and its schema checked; errors name the file."""
    refuse_half_written(path.parent, path)
    document = parse_json(path, read_bytes(path, "result"))
    schema = document.get("schema") if isinstance(document, dict) else None
    if schema != RESULT_SCHEMA:
        if isinstance(schema, str) and schema.startswith("ufcsr-result/"):
            hint = f"a version this package does not know (it reads {RESULT_SCHEMA}); update ufcsr"
        else:
            hint = f"not a ufcsr result (expected {RESULT_SCHEMA})"
        raise UfcsrError(f"{path}: schema {schema!r}: {hint}")
    return document


def _check_result(path: Path, document: dict[str, Any]) -> None:
    """The fields the package uses, checked as the analyzer checks them (a typed error naming
    the file and the field, never a bare KeyError, a fractional count or NaN taken as data)."""
    images = field(path, document, "images", dict)
    for name in ("found", "failed"):
        count(path, images, name, f"images.{name}")
    count(path, document, "grand_total", "grand_total")
    settings = field(path, document, "settings", dict)
    field(path, settings, "archive", str, "settings.archive")
    _palette_size(path, document)
    for index, part in enumerate(field(path, document, "parts", list, required=False) or []):
        where = f"parts[{index}]"
        if not isinstance(part, dict):
            raise UfcsrError(f"{path}: {where}: expected an object, got {type(part).__name__}")
        field(path, part, "name", str, f"{where}.name")
        for name in PART_COUNTS:
            count(path, part, name, f"{where}.{name}")
        for name in ("average", "share", "coverage"):
            number(path, part, name, f"{where}.{name}")
    for name in ("warnings",):
        field(path, document, name, list, required=False)


def _parts_frame(summary: dict[str, Any]) -> pd.DataFrame:
    """One row per legend part, indexed by part name, plus the measures when present."""
    rows = [[part.get(name) for name in PART_FIELDS] for part in summary.get("parts", [])]
    parts = pd.DataFrame(rows, columns=PART_COLUMNS)
    measures = (summary.get("measures") or {}).get("parts") or []
    # The measures list the legend's parts in legend order, then "(unlabelled)".
    names = [measure.get("name") if isinstance(measure, dict) else None for measure in measures[: len(parts)]]
    if measures and names == list(parts["name"]):
        for column in MEASURE_COLUMNS:
            parts[column] = [measure.get(column) for measure in measures[: len(parts)]]
    return parts.set_index("name", drop=False).rename_axis("part")


def decode_texel_counts(path: Path, document: dict[str, Any]) -> np.ndarray:
    """result.json's delta-encoded counts as a dense uint32 array of the palette's size."""
    width, height = _palette_size(path, document)
    encoded = document.get("texel_counts")
    if not isinstance(encoded, dict) or encoded.get("encoding") != "delta":
        raise UfcsrError(f"{path}: texel_counts: expected delta encoding")
    deltas = _integers(path, encoded, "texel_delta")
    counts = _integers(path, encoded, "count")
    if deltas.ndim != 1 or deltas.shape != counts.shape:
        raise UfcsrError(f"{path}: texel_counts: expected delta encoding with arrays of equal length")
    if encoded.get("texels") != len(counts):
        raise UfcsrError(
            f"{path}: texel_counts: \"texels\" says {encoded.get('texels')} but {len(counts)} counts follow "
            "(edited or truncated?)"
        )
    texels = np.cumsum(deltas)
    if len(deltas) and (deltas[0] < 0 or (deltas[1:] <= 0).any()):
        raise UfcsrError(f"{path}: texel_counts: texels must be listed once each, in increasing order")
    if len(texels) and texels[-1] >= width * height:
        raise UfcsrError(f"{path}: texel_counts: texel {int(texels[-1])} is outside the palette")
    if (counts <= 0).any() or (counts > np.iinfo(np.uint32).max).any():
        raise UfcsrError(f"{path}: texel_counts: counts must be 1 to 2**32 - 1 (only seen texels are listed)")
    dense = np.zeros(width * height, dtype=np.uint32)
    dense[texels] = counts.astype(np.uint32)
    return dense


def _integers(path: Path, encoded: dict[str, Any], name: str) -> np.ndarray:
    """``texel_counts.NAME``: a list of whole numbers (no fractions, no NaN, no text) as int64."""
    values = encoded.get(name, [])
    if not isinstance(values, list) or not all(
        isinstance(v, int) and not isinstance(v, bool) and -(1 << 62) < v < 1 << 62 for v in values
    ):
        raise UfcsrError(f"{path}: texel_counts.{name}: expected a list of whole numbers")
    return np.asarray(values, dtype=np.int64)


def _palette_size(path: Path, document: dict[str, Any]) -> tuple[int, int]:
    settings = document.get("settings")
    palette = settings.get("palette") if isinstance(settings, dict) else None
    palette = palette if isinstance(palette, dict) else {}
    width, height = palette.get("width"), palette.get("height")
    whole = all(isinstance(v, int) and not isinstance(v, bool) and v > 0 for v in (width, height))
    if not (whole and width * height <= MAX_TEXELS):
        raise UfcsrError(f"{path}: settings.palette is {width!r}×{height!r}: not a palette size")
    return width, height


def decode_texel_area(path: Path, data: bytes, width: int, height: int) -> np.ndarray:
    """texel-area.f32's values (deg²·s per texel) as a float32 array of the palette's size,
    checked as the analyzer checks them (src/result/texel_area_file.rs): magic, size, every
    value finite and at least 0."""
    header = len(TEXEL_AREA_MAGIC) + 8
    if len(data) < header or data[: len(TEXEL_AREA_MAGIC)] != TEXEL_AREA_MAGIC:
        raise UfcsrError(f"{path}: not a ufcsr texel-area.f32 (ufcsr-texel-area/1) file")
    w, h = np.frombuffer(data[len(TEXEL_AREA_MAGIC) : header], dtype="<u4")
    if (int(w), int(h)) != (width, height):
        raise UfcsrError(f"{path}: holds a {w}×{h} raster but the result's palette is {width}×{height}")
    if len(data) != header + width * height * 4:
        raise UfcsrError(
            f"{path}: {len(data)} bytes where a {width}×{height} raster takes {header + width * height * 4} "
            "(truncated or edited?)"
        )
    values = np.frombuffer(data[header:], dtype="<f4").astype(np.float32)
    bad = np.flatnonzero(~np.isfinite(values) | (values < 0))
    if len(bad):
        raise UfcsrError(f"{path}: texel {int(bad[0])} holds {values[bad[0]]}: not an angular area (finite, ≥ 0)")
    return values


class Result:
    """One analysis result: ``result.json`` and ``frames.csv`` of a results folder.

    Attributes:
        path: the result.json read.
        parts: pandas DataFrame, one row per legend part, indexed by part name
            (``result.parts.loc["grill"]``): name, color, texels, total, peak,
            average, share_percent, coverage_percent, texels_seen (parts.csv's
            names), and with frames tallied
            pixels, eye_frames_seen, angular_area_deg2_s, exposure_s.
        frames: frames.csv as a DataFrame (one row per eye-frame and part), or
            None when the analysis wrote none.
        texel_counts: numpy uint32 array of the palette's size, the count per
            texel index (``y * width + x``), decoded on first use.
        texel_area: numpy float32 array of the palette's size, deg²·s per
            texel (texel-area.f32, ``--texel-area on``), or None.
        summary: the rest of result.json as a dict (images, settings,
            warnings, measures, ...).
    """

    def __init__(self, path: PathLike):
        self.path: Path = result_json_path(path)
        document = _document(self.path)
        _check_result(self.path, document)
        self._encoded = document.pop("texel_counts", None)
        self.parts: pd.DataFrame = _parts_frame(document)
        document.pop("parts", None)
        self.summary: dict[str, Any] = document
        frames = self.path.parent / FRAMES_FILE
        self.frames: Optional[pd.DataFrame] = None
        if os.path.lexists(frames):
            self.frames = read_table(frames)

    @cached_property
    def texel_counts(self) -> np.ndarray:
        document = {"settings": self.summary.get("settings"), "texel_counts": self._encoded}
        return decode_texel_counts(self.path, document)

    @cached_property
    def texel_area(self) -> Optional[np.ndarray]:
        """texel-area.f32 beside result.json (deg²·s per texel, ``--texel-area on``) as a float32
        array of the palette's size, or None when the analysis measured none."""
        path = self.path.parent / TEXEL_AREA_FILE
        if not os.path.lexists(path):
            return None
        width, height = self.palette_size
        data = read_bytes(path, "result")
        return decode_texel_area(path, data, width, height)

    @property
    def palette_size(self) -> tuple[int, int]:
        """(width, height) of the palette the texel indices address."""
        return _palette_size(self.path, self.summary)

    @property
    def grand_total(self) -> int:
        """Sum of the part totals over legend parts (without a PIdT: over all texels)."""
        return int(self.summary["grand_total"])

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

    Raises :class:`ufcsr.UfcsrError` (naming the file) when it is missing, not
    a regular file, too large, or not a ufcsr result.
    """
    return Result(path)
