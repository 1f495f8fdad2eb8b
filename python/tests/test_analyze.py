"""ufcsr.analyze and ufcsr.read_result on the bundled example: the known
answers, and the same files as `ufcsr-analyze` writes."""

import json
import shutil
import warnings

import numpy as np
import pandas as pd
import pytest

import ufcsr
from conftest import EXAMPLE

# The bundled example's known answers (README, tests/known_answers.rs).
GRAND_TOTAL = 52_944
TILES_FOUND = 500
GRILL_TOTAL = 9_231
PALETTE_SIDE = 512


def decode_texel_counts_in_python(result_json):
    """result.json's delta-encoded counts, expanded with plain Python (the reference)."""
    document = json.loads(result_json.read_text())
    palette = document["settings"]["palette"]
    dense = np.zeros(palette["width"] * palette["height"], dtype=np.uint32)
    encoded = document["texel_counts"]
    dense[np.cumsum(encoded["texel_delta"])] = encoded["count"]
    return dense


def test_example_gives_the_known_totals(example_result):
    assert example_result.grand_total == GRAND_TOTAL
    assert example_result.summary["images"]["found"] == TILES_FOUND
    grill = example_result.parts.set_index("name").loc["grill"]
    assert grill["total"] == GRILL_TOTAL
    assert example_result.complete


def test_parts_have_the_report_columns_one_row_per_legend_part(example_result):
    parts = example_result.parts
    assert isinstance(parts, pd.DataFrame)
    legend = pd.read_csv(EXAMPLE / "parts.csv")
    assert list(parts["name"]) == list(legend["name"])
    # parts.csv's names: the unit in the name.
    expected = [
        "name", "color", "texels", "total", "peak", "average", "share_percent", "coverage_percent", "texels_seen"
    ]
    assert list(parts.columns[: len(expected)]) == expected
    assert {"pixels", "eye_frames_seen", "exposure_s"} <= set(parts.columns), "measures joined"
    assert parts["total"].sum() == GRAND_TOTAL
    assert parts["share_percent"].sum() == pytest.approx(100.0)
    table = pd.read_csv(example_result.path.parent / "parts.csv")
    assert {"share_percent", "coverage_percent"} <= set(table.columns), "one name in both"
    assert "parts" not in example_result.summary, "the parts live in .parts"


def test_parts_are_indexed_by_part_name(example_result):
    parts = example_result.parts
    assert parts.index.name == "part"
    assert list(parts.index) == list(parts["name"])
    assert parts.loc["grill", "total"] == GRILL_TOTAL


def test_analysis_through_python_writes_the_same_files_as_the_cli(example_result, cli_result_folder):
    ours = example_result.path.parent
    for name in ["result.json", "parts.csv", "frames.csv", "heatmap.png"]:
        assert (ours / name).read_bytes() == (cli_result_folder / name).read_bytes(), name
    reference = json.loads((cli_result_folder / "result.json").read_text())
    assert reference["grand_total"] == GRAND_TOTAL
    grill = next(part for part in reference["parts"] if part["name"] == "grill")
    assert grill["total"] == GRILL_TOTAL


def test_texel_counts_are_the_decoded_delta_encoding(example_result):
    counts = example_result.texel_counts
    assert counts.dtype == np.uint32
    assert counts.shape == (PALETTE_SIDE * PALETTE_SIDE,)
    np.testing.assert_array_equal(counts, decode_texel_counts_in_python(example_result.path))
    assert int(counts.sum()) == GRAND_TOTAL, "no counts on unlabelled texels in the example"
    assert int(np.count_nonzero(counts)) == example_result.summary["texels_seen"]
    assert int(counts.max()) == example_result.summary["max_count"]


def test_frames_is_frames_csv_as_a_dataframe(example_result):
    frames = example_result.frames
    assert list(frames.columns) == ["frame", "time_s", "eye", "distance_m", "part", "pixels", "texels", "solid_angle_sr"]
    pixels_by_part = frames.groupby("part")["pixels"].sum()
    parts = example_result.parts.set_index("name")
    assert (pixels_by_part[parts.index] == parts["pixels"]).all()


def test_read_result_takes_the_folder_or_the_file(example_result):
    folder = example_result.path.parent
    by_folder = ufcsr.read_result(folder)
    by_file = ufcsr.read_result(folder / "result.json")
    assert by_folder.path == by_file.path == example_result.path
    pd.testing.assert_frame_equal(by_folder.parts, by_file.parts)
    assert by_folder.summary == by_file.summary


def test_repr_says_what_it_is(example_result):
    text = repr(example_result)
    assert text.startswith("<ufcsr.Result of ")
    assert "48 parts" in text and "52,944" in text and "512×512" in text


def test_without_frames_csv_frames_is_none(program, tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ufcsr.UfcsrWarning)
        result = ufcsr.analyze(EXAMPLE, out=tmp_path, frames_csv=False, threads=1)
    assert result.frames is None
    assert result.grand_total == GRAND_TOTAL, "one thread counts the same"


def test_default_output_folder_is_the_analyzers(program, tmp_path):
    archive = tmp_path / "example"
    shutil.copytree(EXAMPLE, archive)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ufcsr.UfcsrWarning)
        result = ufcsr.analyze(archive)
    assert result.path == archive / "results" / "result.json"
    assert result.grand_total == GRAND_TOTAL
