"""ufcsr.heatmap draws with the library's heatmap: the same PNG as the
analyzer's for the same counts and scale."""

import struct

import numpy as np
import pytest

import ufcsr


def png_size(path):
    """(width, height) from a PNG's IHDR chunk."""
    header = path.read_bytes()[:24]
    assert header[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", header[16:24])


def test_default_heatmap_equals_the_analyzers_count_heatmap(example_result, tmp_path):
    # ufcsr.heatmap draws the counts: the analysis' heatmap-count.png (its
    # heatmap.png shows the per-texel angular area), or heatmap.png without one.
    out = ufcsr.heatmap(example_result, tmp_path / "heatmap.png")
    folder = example_result.path.parent
    count = folder / "heatmap-count.png"
    assert count.is_file(), "the example measures per-texel angular area"
    assert out.read_bytes() == count.read_bytes()
    assert out.read_bytes() != (folder / "heatmap.png").read_bytes()
    assert png_size(out) == example_result.palette_size


def test_log_scale_and_max_change_the_picture(example_result, tmp_path):
    linear = ufcsr.heatmap(example_result.path.parent, tmp_path / "linear.png", scale="linear")
    log = ufcsr.heatmap(example_result, tmp_path / "log.png", scale="log")
    capped = ufcsr.heatmap(example_result, tmp_path / "capped.png", max=2)
    assert len({linear.read_bytes(), log.read_bytes(), capped.read_bytes()}) == 3


def test_counts_changed_in_python_are_drawn(example_result, tmp_path):
    result = ufcsr.read_result(example_result.path)
    result.texel_counts = np.zeros_like(result.texel_counts)
    blank = ufcsr.heatmap(result, tmp_path / "blank.png")
    default = ufcsr.heatmap(example_result, tmp_path / "default.png")
    assert blank.read_bytes() != default.read_bytes()


def test_bad_scale_and_max_are_refused(example_result, tmp_path):
    with pytest.raises(ufcsr.UfcsrError, match="linear or log"):
        ufcsr.heatmap(example_result, tmp_path / "x.png", scale="sqrt")
    with pytest.raises(ufcsr.UfcsrError, match="at least 1"):
        ufcsr.heatmap(example_result, tmp_path / "x.png", max=0)
