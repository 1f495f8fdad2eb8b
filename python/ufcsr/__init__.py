"""ufcsr from Python: run the visibility analysis, read its results, draw heatmaps.

Pure Python: ``pip install ./python`` compiles nothing. Reading results
(parts, frames, per-texel counts, placement, study and observer outputs) needs
only numpy and pandas; :func:`analyze` and :func:`heatmap` run the installed
``ufcsr-analyze`` program, so the numbers are exactly the ones it prints.

    >>> import ufcsr
    >>> result = ufcsr.analyze("fixtures/example", out="/tmp/example-results")
    >>> result.parts.nlargest(5, "share_percent")[["total", "share_percent"]]
"""

from __future__ import annotations

import json
import os
import tempfile
import warnings
from pathlib import Path
from typing import Literal, Optional, Sequence, Union

import numpy as np

from ._files import PathLike, UfcsrError
from ._outputs import Outputs, read_observers, read_placement, read_study
from ._program import find_program, run
from ._result import RESULT_SCHEMA, Result, read_result

__version__ = "0.1.0"

__all__ = [
    "Outputs",
    "Result",
    "UfcsrError",
    "UfcsrWarning",
    "__version__",
    "analyze",
    "heatmap",
    "read_observers",
    "read_placement",
    "read_result",
    "read_study",
]

Pair = Union[str, tuple[int, int]]


class UfcsrWarning(UserWarning):
    """What ``ufcsr-analyze`` prints as ``warning:`` (result.json's warnings, failed images)."""


def _integer(name: str, value: object) -> Optional[int]:
    if value is None:
        return None
    if isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_)):
        return int(value)
    raise TypeError(f"option {name}: expected an int, got {type(value).__name__}")


def _flag(name: str, value: object) -> bool:
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    raise TypeError(f"option {name}: expected True or False, got {value!r}")


def _text(name: str, value: object) -> str:
    if isinstance(value, str):
        return value
    raise TypeError(f"option {name}: expected a str, got {type(value).__name__}")


def _pair(name: str, value: Pair, separator: str) -> str:
    """``"WxH"`` / ``"I/N"`` as text, or from a (first, second) tuple."""
    if isinstance(value, (tuple, list)) and len(value) == 2:
        return f"{_integer(name, value[0])}{separator}{_integer(name, value[1])}"
    return _text(name, value)


def _option(arguments: list[str], flag: str, value: Optional[str]) -> None:
    if value is not None:
        arguments += [flag, value]


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


def analyze(
    archive: PathLike,
    out: Optional[PathLike] = None,
    *,
    pidt: Optional[PathLike] = None,
    parts: Optional[PathLike] = None,
    fcsp: Optional[PathLike] = None,
    palette_size: Optional[Pair] = None,
    background: Union[str, Sequence[str], None] = None,
    dedupe: Literal["image", "frame", "eye-pair", "eye_pair"] = "image",
    trim: Union[Literal["auto", "off"], int] = "auto",
    scale: Literal["linear", "log"] = "linear",
    max: Optional[int] = None,
    shard: Optional[Pair] = None,
    mesh: Optional[PathLike] = None,
    frames_csv: bool = True,
    csv_style: Literal["report", "paper"] = "report",
    figures: bool = False,
    threads: Optional[int] = None,
    strict: bool = False,
    strict_colors: bool = False,
    no_manifest: bool = False,
    progress: bool = False,
    executable: Optional[PathLike] = None,
) -> Result:
    """Analyses ``archive`` as ``ufcsr-analyze ARCHIVE --out OUT`` does, and reads the result back.

    Writes the full result set (result.json, parts.csv, heatmap.png,
    frames.csv, report.html, ...) to ``out`` (default ``ARCHIVE/results``, as
    the command line) and returns it as a :class:`Result`. The figures (plots,
    views, map, frame strip) take most of a small analysis and a notebook
    wants the tables: they are left out unless ``figures=True`` (the command
    line's ``--figures on``); the tables are the same either way. The options are
    the command line's (``ufcsr-analyze --help``): ``pidt``, ``parts`` (the
    legend), ``fcsp`` or ``palette_size`` ("WxH" or (w, h)), ``background``
    ("#RRGGBB" or a list), ``dedupe``, ``trim`` ("auto", "off" or bytes),
    ``scale``, ``max``, ``shard`` ("I/N" or (i, n); default from the job
    array's environment), ``mesh``, ``frames_csv``, ``csv_style``,
    ``threads`` (default all cores), ``strict``, ``strict_colors``,
    ``no_manifest``. ``progress=True`` shows the program's progress bar on
    stderr. ``executable`` is the ``ufcsr-analyze`` to run (default: the
    ``UFCSR_ANALYZE`` variable, then PATH).

    Raises TypeError for a value of the wrong type, ``UfcsrError`` with the
    analyzer's message (naming the file) when the analysis fails. Ctrl-C
    stops the analysis within a second, leaves ``out`` as it was and raises
    KeyboardInterrupt. Warnings come as UfcsrWarning; images that failed
    leave ``result.complete`` False (``strict=True`` raises instead).
    """
    if fcsp is not None and palette_size is not None:
        raise ValueError("options fcsp and palette_size exclude each other: give one palette")
    out_dir = Path(os.fspath(archive)) / "results" if out is None else Path(os.fspath(out))
    arguments = [os.fspath(archive), "--out", os.fspath(out_dir), "--quiet"]
    for flag, path in (("--pidt", pidt), ("--legend", parts), ("--fcsp", fcsp), ("--mesh", mesh)):
        _option(arguments, flag, None if path is None else os.fspath(path))
    _option(arguments, "--palette-size", None if palette_size is None else _pair("palette_size", palette_size, "x"))
    for color in [background] if isinstance(background, str) else list(background or []):
        _option(arguments, "--background", _text("background", color))
    _option(arguments, "--dedupe", _text("dedupe", dedupe).replace("_", "-"))
    _option(arguments, "--trim", str(trim) if isinstance(trim, (int, np.integer)) else _text("trim", trim))
    _option(arguments, "--scale", _text("scale", scale))
    _option(arguments, "--max", None if max is None else str(_integer("max", max)))
    _option(arguments, "--shard", None if shard is None else _pair("shard", shard, "/"))
    _option(arguments, "--frames-csv", "on" if _flag("frames_csv", frames_csv) else "off")
    _option(arguments, "--csv-style", _text("csv_style", csv_style))
    _option(arguments, "--figures", "on" if _flag("figures", figures) else "off")
    _option(arguments, "--threads", None if threads is None else str(_integer("threads", threads)))
    for flag, name, value in (
        ("--strict", "strict", strict),
        ("--strict-colors", "strict_colors", strict_colors),
        ("--no-manifest", "no_manifest", no_manifest),
    ):
        if _flag(name, value):
            arguments.append(flag)
    program = find_program(executable)
    if progress:
        arguments.remove("--quiet")
    existed = os.path.lexists(out_dir)
    try:
        run(program, arguments, _flag("progress", progress))
    except KeyboardInterrupt:
        _remove_if_empty(out_dir, existed)
        raise
    result = read_result(out_dir)
    _warn(result)
    return result


def _remove_if_empty(out_dir: Path, existed: bool) -> None:
    """After Ctrl-C: the output folder this call created is removed when nothing was put in it
    (the program leaves earlier outputs untouched, but it may have created the folder)."""
    if existed:
        return
    try:
        if out_dir.is_dir() and not out_dir.is_symlink() and not any(out_dir.iterdir()):
            out_dir.rmdir()
    except OSError:
        pass


def _write_counts(folder: Path, result: Result, counts: np.ndarray) -> Path:
    """A result.json holding ``result``'s settings and ``counts``: what ``ufcsr-analyze heatmap`` reads."""
    seen = np.flatnonzero(counts)
    deltas = np.diff(seen, prepend=0) if len(seen) else seen
    document = {
        "schema": RESULT_SCHEMA,
        "measure": result.summary.get("measure", "pixels"),
        "settings": result.summary["settings"],
        "texel_counts": {
            "encoding": "delta",
            "texels": int(len(seen)),
            "texel_delta": deltas.tolist(),
            "count": counts[seen].tolist(),
        },
    }
    path = folder / "result.json"
    path.write_text(json.dumps(document))
    return path


def _refuse_output(out: Path, source: Path) -> None:
    """``out`` may be a new file or a regular file that is not the result read: never an input or a device."""
    if not os.path.lexists(out):
        return
    if out.is_symlink() or not out.is_file():
        raise UfcsrError(f"{out}: exists and is not a regular file: the heatmap is not written over it")
    if out.resolve() == source.resolve() or out.name == source.name:
        raise UfcsrError(f"{out}: is the result being drawn: the heatmap is not written over its input")


def heatmap(
    result: Union[Result, PathLike],
    out: PathLike,
    scale: Optional[Literal["linear", "log"]] = None,
    max: Optional[int] = None,
    *,
    executable: Optional[PathLike] = None,
) -> Path:
    """Writes the count heatmap texture of ``result`` (a Result, a result.json or its folder) to ``out``.

    This is the paper-compatible count (the analysis' ``heatmap-count.png``,
    or its ``heatmap.png`` with ``--texel-area off``); the analysis'
    ``heatmap.png`` shows the per-texel angular area when it was measured.

    ``scale`` is "linear" or "log", ``max`` the count shown at the top of the
    colour scale (larger counts clamp); by default the result's own settings
    (as ``ufcsr-analyze heatmap``). The counts are ``result.texel_counts``,
    so an array changed in Python is drawn as it is now, by the analyzer's
    own heatmap code. Returns ``out``.
    """
    if not isinstance(result, Result):
        result = read_result(result)
    if scale is not None and scale not in ("linear", "log"):
        raise UfcsrError(f"scale {scale!r}: the heatmap's scale is linear or log")
    if max is not None and _integer("max", max) < 1:
        raise UfcsrError(f"max {max}: the top of the colour scale must be at least 1")
    counts = np.asarray(result.texel_counts)
    if counts.shape != (result.palette_size[0] * result.palette_size[1],):
        raise ValueError(f"texel_counts must have one count per texel ({result.palette_size[0]}×{result.palette_size[1]})")
    if counts.size and (counts.min() < 0 or counts.max() > np.iinfo(np.uint32).max):
        raise ValueError("texel_counts must be counts from 0 to 2**32 - 1")
    _refuse_output(Path(os.fspath(out)), result.path)
    program = find_program(executable)
    with tempfile.TemporaryDirectory(prefix="ufcsr-heatmap-") as folder:
        source = _write_counts(Path(folder), result, counts.astype(np.uint32))
        arguments = ["heatmap", os.fspath(source), "--out", os.fspath(out), "--quiet"]
        _option(arguments, "--scale", scale)
        _option(arguments, "--max", None if max is None else str(max))
        run(program, arguments, False)
    return Path(os.fspath(out))
