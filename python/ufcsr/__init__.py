"""ufcsr from Python: run the visibility analysis, read its results, draw heatmaps.

The counting, the decoding of result.json's texel counts and the heatmap are
the analyzer's own Rust code (``ufcsr._native``), so the numbers are the ones
``ufcsr-analyze`` prints. This layer checks option names, shapes their values
and hands results over as pandas DataFrames and numpy arrays.

    >>> import ufcsr
    >>> result = ufcsr.analyze("fixtures/example", out="results")
    >>> result.parts.nlargest(5, "share")[["name", "total", "share"]]
"""

from __future__ import annotations

import difflib
import os
import warnings
from pathlib import Path
from typing import Any, Optional, Union

import numpy as np

from . import _native
from ._result import PathLike, Result, read_result

UfcsrError = _native.UfcsrError

__all__ = ["OPTIONS", "Result", "UfcsrError", "UfcsrWarning", "analyze", "heatmap", "read_result"]


class UfcsrWarning(UserWarning):
    """What ``ufcsr-analyze`` prints as ``warning:`` (result.json's warnings, failed images)."""


def _path(name: str, value: Any) -> Optional[str]:
    return None if value is None else os.fspath(value)


def _text(name: str, value: Any) -> Optional[str]:
    if value is None or isinstance(value, str):
        return value
    raise TypeError(f"option {name}: expected a str, got {type(value).__name__}")


def _integer(name: str, value: Any) -> Optional[int]:
    if value is None or (isinstance(value, (int, np.integer)) and not isinstance(value, bool)):
        return None if value is None else int(value)
    raise TypeError(f"option {name}: expected an int, got {type(value).__name__}")


def _flag(name: str, value: Any) -> bool:
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise TypeError(f"option {name}: expected True or False, got {value!r}")


def _pair(name: str, value: Any, separator: str) -> Optional[str]:
    """``"WxH"`` / ``"I/N"`` as text, or from a (first, second) tuple."""
    if isinstance(value, (tuple, list)) and len(value) == 2:
        return f"{_integer(name, value[0])}{separator}{_integer(name, value[1])}"
    return _text(name, value)


def _background(name: str, value: Any) -> list[str]:
    if value is None:
        return []
    colors = [value] if isinstance(value, str) else list(value)
    return [_text(name, color) for color in colors]


def _trim(name: str, value: Any) -> Optional[str]:
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        return str(int(value))
    return _text(name, value)


def _frames_csv(name: str, value: Any) -> bool:
    if value in ("on", "off"):
        return value == "on"
    return _flag(name, value)


def _dedupe(name: str, value: Any) -> Optional[str]:
    text = _text(name, value)
    return None if text is None else text.replace("_", "-")


# Every option of `ufcsr-analyze ARCHIVE`, by its name in snake_case: the
# value's check and shape, and the command line's default.
OPTIONS: dict[str, tuple[Any, Any]] = {
    "pidt": (_path, None),
    "parts": (_path, None),
    "fcsp": (_path, None),
    "palette_size": (lambda name, value: _pair(name, value, "x"), None),
    "background": (_background, None),
    "dedupe": (_dedupe, "image"),
    "trim": (_trim, "auto"),
    "scale": (_text, "linear"),
    "max": (_integer, None),
    "shard": (lambda name, value: _pair(name, value, "/"), None),
    "mesh": (_path, None),
    "frames_csv": (_frames_csv, True),
    "threads": (_integer, None),
    "strict": (_flag, False),
    "no_manifest": (_flag, False),
}


def _unknown_option(name: str) -> TypeError:
    close = difflib.get_close_matches(name, OPTIONS, n=1)
    hint = f" (did you mean {close[0]!r}?)" if close else ""
    return TypeError(
        f"analyze() got an unknown option {name!r}{hint}; options are: {', '.join(sorted(OPTIONS))}"
    )


def _analysis_options(options: dict[str, Any]) -> dict[str, Any]:
    """All options, checked and shaped for the native module, defaults filled in."""
    for name in options:
        if name not in OPTIONS:
            raise _unknown_option(name)
    if options.get("fcsp") is not None and options.get("palette_size") is not None:
        raise ValueError("options fcsp and palette_size exclude each other: give one palette")
    values = {}
    for name, (shape, default) in OPTIONS.items():
        value = options.get(name, default)
        values[name] = shape(name, value if value is not None else default)
    return values


def _warn(result: Result) -> None:
    """Passes on what ``ufcsr-analyze`` prints as warnings, as UfcsrWarning."""
    summary = result.summary
    for warning in summary.get("warnings", []):
        warnings.warn(warning, UfcsrWarning, stacklevel=3)
    stray = summary.get("images_with_stray_pixels", [])
    if stray:
        warnings.warn(
            f"{len(stray)} images have stray pixels (neither background nor palette), e.g. "
            f"{stray[0]['file']}: see summary['images_with_stray_pixels']",
            UfcsrWarning,
            stacklevel=3,
        )
    images = summary["images"]
    if images["failed"]:
        warnings.warn(
            f"{images['failed']} of {images['found']} images failed and were not counted "
            f"(see summary['failures']); results cover the rest",
            UfcsrWarning,
            stacklevel=3,
        )


def analyze(archive: PathLike, out: Optional[PathLike] = None, **options: Any) -> Result:
    """Analyses ``archive`` in-process, as ``ufcsr-analyze ARCHIVE --out OUT`` does.

    Writes the full result set (result.json, parts.csv, heatmap.png,
    frames.csv, report.html, ...) to ``out`` (default: the analyzer's default,
    ``ARCHIVE/results``) and returns it read back as a :class:`Result`.

    Options are the command line's, in snake_case, with its defaults:
    ``pidt``, ``parts`` (legend), ``fcsp`` or ``palette_size`` ("WxH" or
    (w, h)), ``background`` ("#RRGGBB" or a list), ``dedupe`` ("image",
    "frame", "eye-pair"), ``trim`` ("auto", "off" or bytes), ``scale``
    ("linear", "log"), ``max``, ``shard`` ("I/N" or (i, n); default from
    the job array's environment, as the command line), ``mesh``,
    ``frames_csv`` (True), ``threads`` (default all cores), ``strict``,
    ``no_manifest``.

    Raises TypeError for an unknown option or a value of the wrong type,
    ``UfcsrError`` with the analyzer's message (naming the file) when the
    analysis fails. Warnings the command line prints come as UfcsrWarning;
    images that failed leave ``result.complete`` False (``strict=True``
    raises instead).
    """
    values = _analysis_options(options)
    folder = _native.analyze(os.fspath(archive), None if out is None else os.fspath(out), values)
    result = read_result(folder)
    _warn(result)
    return result


def heatmap(
    result: Union[Result, PathLike],
    out: PathLike,
    scale: Optional[str] = None,
    max: Optional[int] = None,
) -> Path:
    """Writes the heatmap PNG of ``result`` (a Result, a result.json or its folder) to ``out``.

    ``scale`` is "linear" or "log", ``max`` the count shown at the top of the
    colour scale (larger counts clamp); by default the result's own settings
    (as ``ufcsr-analyze heatmap``). The counts are ``result.texel_counts``,
    so an array changed in Python is drawn as it is now. Returns ``out``.
    """
    if not isinstance(result, Result):
        result = read_result(result)
    settings = result.summary["settings"]
    scale = settings.get("heatmap_scale", "linear") if scale is None else _text("scale", scale)
    max = settings.get("heatmap_max") if max is None else _integer("max", max)
    counts = np.asarray(result.texel_counts)
    if counts.dtype != np.uint32:
        if counts.size and (counts.min() < 0 or counts.max() > np.iinfo(np.uint32).max):
            raise ValueError("texel_counts must be counts from 0 to 2**32 - 1")
        counts = counts.astype(np.uint32)
    width, height = result.palette_size
    little_endian = np.ascontiguousarray(counts, dtype="<u4")
    _native.write_heatmap(os.fspath(out), little_endian.tobytes(), width, height, scale, max)
    return Path(os.fspath(out))
