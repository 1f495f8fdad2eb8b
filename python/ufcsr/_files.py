"""Reading the files of a result set safely, by the same rules as the analyzer.

Every file this package reads comes through :func:`read_bytes`: it is opened
without blocking (a FIFO named ``result.json`` must not hang a notebook), it
must be a regular file once open (not a device, a FIFO or a folder), and it is
read only up to a size cap from one table, so a link to ``/dev/zero`` or a
runaway file gives an error naming the file instead of eating the machine's
memory. Links are followed (a result folder may be linked), but what they
reach must pass the same checks. Errors name the file and the problem.
"""

from __future__ import annotations

import json
import math
import os
import stat
from pathlib import Path
from typing import TYPE_CHECKING, Any, Optional, Union

if TYPE_CHECKING:
    import pandas as pd

PathLike = Union[str, "os.PathLike[str]"]

# Size caps per kind of file, as the analyzer's (src/files/limited_read.rs):
# a result.json at 4096² holds up to 16.8 M texels of counts; tables and the
# small JSON files of placement, study and observers are far smaller.
LIMITS = {
    "result": 1 << 31,
    "table": 1 << 30,
    "small": 64 << 20,
}

# The analyzer's commit journal: a result set whose move into place a killed
# run left unfinished (docs/reliability.md).
COMMIT_JOURNAL = ".ufcsr-commit.json"


class UfcsrError(Exception):
    """A ufcsr file or run failed; the message names the file and the problem."""


def read_bytes(path: PathLike, kind: str = "small") -> bytes:
    """The bytes of ``path``, a regular file of at most ``LIMITS[kind]`` bytes."""
    path = Path(os.fspath(path))
    limit = LIMITS[kind]
    try:
        descriptor = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except FileNotFoundError:
        raise UfcsrError(f"{path}: no such file") from None
    except OSError as error:
        raise UfcsrError(f"{path}: cannot open: {error.strerror}") from None
    # Checked before the descriptor becomes a file object: os.fdopen of a folder raises a bare
    # IsADirectoryError naming no file.
    info = os.fstat(descriptor)
    if not stat.S_ISREG(info.st_mode):
        os.close(descriptor)
        raise UfcsrError(f"{path}: not a regular file (a folder, device, FIFO or socket)")
    with os.fdopen(descriptor, "rb") as handle:
        if info.st_size > limit:
            raise UfcsrError(f"{path}: {info.st_size:,} bytes, more than the {limit:,} bytes a {kind} file may have")
        data = handle.read(limit + 1)
    if len(data) > limit:
        raise UfcsrError(f"{path}: more than the {limit:,} bytes a {kind} file may have (it grew while read)")
    return data


def _refuse_constant(name: str) -> float:
    raise ValueError(f"{name} is not a JSON number")


def parse_json(path: PathLike, data: bytes) -> Any:
    """``data`` (the bytes of ``path``) parsed as JSON, strictly: NaN and Infinity are refused (JSON
    has neither), and too deep a nesting or a malformed file is an error naming the file, never a
    bare RecursionError or ValueError."""
    try:
        return json.loads(data, parse_constant=_refuse_constant)
    except RecursionError:
        raise UfcsrError(f"{os.fspath(path)}: nested too deeply to be a ufcsr file") from None
    except (ValueError, UnicodeDecodeError) as error:
        raise UfcsrError(f"{os.fspath(path)}: not valid JSON: {error}") from None


def field(path: PathLike, document: Any, name: str, kind: type, where: Optional[str] = None, required: bool = True) -> Any:
    """``document[name]``, which must be a ``kind``; an error naming the file and the field otherwise."""
    where = where or name
    value = document.get(name) if isinstance(document, dict) else None
    if value is None and not required:
        return None
    if not isinstance(value, kind) or (kind is int and isinstance(value, bool)):
        got = "nothing" if value is None else type(value).__name__
        raise UfcsrError(f"{os.fspath(path)}: {where}: expected {_KIND_WORDS.get(kind, kind.__name__)}, got {got}")
    return value


_KIND_WORDS = {dict: "an object", list: "a list", str: "text", int: "a whole number"}


def count(path: PathLike, document: Any, name: str, where: str) -> int:
    """``document[name]``: a whole number of at least 0 (a count), or an error naming the field."""
    value = field(path, document, name, int, where)
    if value < 0:
        raise UfcsrError(f"{os.fspath(path)}: {where}: {value} is negative: not a count")
    return value


def number(path: PathLike, document: Any, name: str, where: str) -> float:
    """``document[name]``: a finite number, or an error naming the field."""
    value = document.get(name) if isinstance(document, dict) else None
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise UfcsrError(f"{os.fspath(path)}: {where}: expected a finite number, got {value!r}")
    return float(value)


def read_table(path: PathLike) -> "pd.DataFrame":
    """A CSV table of a result set (``frames.csv``, placement and study tables) as a DataFrame:
    read by :func:`read_bytes` (regular file, size cap) and parsed by pandas; a table pandas cannot
    parse gives an error naming the file (pandas' own message names no file: it reads bytes)."""
    import io

    import pandas as pd

    data = read_bytes(path, "table")
    try:
        return pd.read_csv(io.BytesIO(data))
    except (ValueError, UnicodeDecodeError, pd.errors.ParserError) as error:
        raise UfcsrError(f"{os.fspath(path)}: not a readable CSV table: {error}") from None


def refuse_half_written(folder: Path, path: Path) -> None:
    """A set whose commit was interrupted is part old, part new: refused, as by the analyzer."""
    journal = folder / COMMIT_JOURNAL
    if os.path.lexists(journal):
        raise UfcsrError(
            f"{path}: its run was killed while it moved a new result set into place ({journal} is left): "
            "the set is part old, part new; analyse again into this folder (that finishes the move first)"
        )
