"""The other outputs read back: placement, study and observer folders.

Each of these commands writes one JSON document and CSV tables beside it
(docs/placement.md, docs/science.md). Reading them needs no native code: the
document comes back as a dict (checked to be the kind asked for, through the
same safe reads as result.json) and every table as a DataFrame, so a notebook
can plot what the command decided from the same numbers.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import pandas as pd

from ._files import PathLike, UfcsrError, parse_json, read_bytes, read_table

# Each output's document, the schema prefix it carries (when it carries one) and its tables.
KINDS = {
    "placement": ("placement.json", "ufcsr-placement/", ("placement.csv", "placement-combinations.csv")),
    "study": ("study.json", "ufcsr-study/", ("study.csv",)),
    # observer-displays.csv (and the document's "displays") only with `observers --display WxH`.
    "observers": (
        "observers.json",
        "ufcsr-observers/",
        ("observers.csv", "observer-parts.csv", "observer-displays.csv"),
    ),
}


class Outputs:
    """A command's output folder: ``document`` (the JSON, a dict) and ``tables`` (DataFrames by file name)."""

    def __init__(self, kind: str, path: PathLike):
        document_name, schema_prefix, table_names = KINDS[kind]
        path = Path(os.fspath(path))
        self.kind = kind
        self.path = path / document_name if path.is_dir() else path
        self.document: dict[str, Any] = parse_json(self.path, read_bytes(self.path, "small"))
        schema = self.document.get("schema") if isinstance(self.document, dict) else None
        if not isinstance(self.document, dict) or (schema is not None and not str(schema).startswith(schema_prefix)):
            raise UfcsrError(f"{self.path}: schema {schema!r}: not a ufcsr {document_name}")
        self.tables: dict[str, pd.DataFrame] = {}
        for name in table_names:
            table = self.path.parent / name
            if os.path.lexists(table):
                self.tables[name] = read_table(table)

    def __repr__(self) -> str:
        tables = ", ".join(f"{name} {len(frame):,} rows" for name, frame in self.tables.items()) or "no tables"
        return f"<ufcsr.Outputs {self.kind} read from {os.fspath(self.path)!r}: {tables}>"


def read_placement(path: PathLike) -> Outputs:
    """``ufcsr-analyze placement``'s folder (or its placement.json): the best placements and their tables."""
    return Outputs("placement", path)


def read_study(path: PathLike) -> Outputs:
    """``ufcsr-capture study``'s folder (or its study.json): error against run time per setting."""
    return Outputs("study", path)


def read_observers(path: PathLike) -> Outputs:
    """``ufcsr-capture observers``' folder (or its observers.json): the spread over pedestrians.

    With ``--display WxH`` the document has ``displays`` (per candidate display the legible seconds
    over the observers, ``summary``, and each observer's, ``observers``) and ``tables`` has
    ``observer-displays.csv``; without it (and in files written before it) neither is there.
    """
    return Outputs("observers", path)
