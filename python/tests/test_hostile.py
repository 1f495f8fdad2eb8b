"""Hostile and malformed files (issue 41 §3): every one is one typed error, UfcsrError, naming the
file and the field — never a bare RecursionError, IndexError, OverflowError, ValueError,
AttributeError or IsADirectoryError, and never accepted as data (fractional counts, a negative
palette, NaN, an empty object). Also the figures-off default, texel-area.f32 and Ctrl-C's folder."""

import json
import os
import stat

import numpy as np
import pytest

import ufcsr
from conftest import EXAMPLE


def minimal_result():
    """The smallest result.json the package reads: a 2×2 palette, one part, two counted texels."""
    return {
        "schema": "ufcsr-result/1",
        "images": {"found": 1, "failed": 0},
        "grand_total": 5,
        "settings": {"archive": "a", "palette": {"width": 2, "height": 2}},
        "parts": [
            {"name": "door", "color": "#ff0000", "texels": 2, "total": 5, "peak": 3, "average": 2.5,
             "share": 100.0, "coverage": 100.0, "texels_seen": 2},
        ],
        "texel_counts": {"encoding": "delta", "texels": 2, "texel_delta": [1, 2], "count": [2, 3]},
    }


def write(tmp_path, document):
    path = tmp_path / "result.json"
    path.write_text(document if isinstance(document, str) else json.dumps(document))
    return path


def refused(path, field, read=lambda result: result.texel_counts, named=None):
    """Reading ``path`` (and ``read`` of it) raises UfcsrError naming the file (``named``, default
    ``path``) and ``field``."""
    with pytest.raises(ufcsr.UfcsrError) as caught:
        read(ufcsr.read_result(path))
    message = str(caught.value)
    assert str(named or path) in message, message
    assert field in message, message
    return message


def test_a_minimal_result_reads(tmp_path):
    result = ufcsr.read_result(write(tmp_path, minimal_result()))
    np.testing.assert_array_equal(result.texel_counts, [0, 2, 0, 3])
    assert list(result.parts["share_percent"]) == [100.0]
    assert result.texel_area is None


def test_deep_nesting_is_refused_naming_the_file(tmp_path):
    path = write(tmp_path, "[" * 100_000 + "]" * 100_000)
    refused(path, "nested too deeply")


def test_nan_and_infinity_are_refused(tmp_path):
    text = json.dumps(minimal_result()).replace('"average": 2.5', '"average": NaN')
    refused(write(tmp_path, text), "NaN")
    text = json.dumps(minimal_result()).replace('"grand_total": 5', '"grand_total": Infinity')
    refused(write(tmp_path, text), "Infinity")


def test_an_empty_object_or_missing_fields_are_refused(tmp_path):
    refused(write(tmp_path, {}), "schema")
    refused(write(tmp_path, {"schema": "ufcsr-result/1"}), "images")
    document = minimal_result()
    del document["settings"]
    refused(write(tmp_path, document), "settings")


def test_fractional_and_negative_counts_are_refused(tmp_path):
    for change, field in [
        (lambda d: d["texel_counts"].update(count=[2.5, 3]), "texel_counts.count"),
        (lambda d: d["texel_counts"].update(texel_delta=[1.0, 2]), "texel_counts.texel_delta"),
        (lambda d: d["parts"][0].update(total=4.5), "parts[0].total"),
        (lambda d: d["parts"][0].update(peak=-1), "parts[0].peak"),
        (lambda d: d.update(grand_total=-5), "grand_total"),
        (lambda d: d["images"].update(found="1"), "images.found"),
    ]:
        document = minimal_result()
        change(document)
        refused(write(tmp_path, document), field)


def test_a_negative_or_odd_palette_is_refused(tmp_path):
    for palette in [{"width": -2, "height": -2}, {"width": 2.0, "height": 2}, [2, 2], {"width": True, "height": 4}]:
        document = minimal_result()
        document["settings"]["palette"] = palette
        refused(write(tmp_path, document), "settings.palette")
    document = minimal_result()
    document["settings"] = ["not", "an", "object"]
    refused(write(tmp_path, document), "settings")


def test_a_palette_of_32_bit_texel_ids_reads_and_an_absurd_one_is_refused(tmp_path):
    # 8192 × 2049 texels (more than 2^24, an rgba32 archive's): a count at the last texel reads.
    document = minimal_result()
    document["settings"]["palette"] = {"width": 8192, "height": 2049}
    last = 8192 * 2049 - 1
    document["texel_counts"]["texel_delta"] = [1, last - 1]
    counts = ufcsr.read_result(write(tmp_path, document)).texel_counts
    assert counts.shape == (2049, 8192) or counts.size == 8192 * 2049
    assert counts.reshape(-1)[last] == 3 and counts.reshape(-1)[1] == 2
    # Beyond 2^26 texels (ufcsr::MAX_RGBA32_TEXELS): no palette ufcsr writes.
    document["settings"]["palette"] = {"width": 8192, "height": 8193}
    refused(write(tmp_path, document), "settings.palette")


def test_huge_numbers_are_refused_not_overflowing(tmp_path):
    document = minimal_result()
    document["texel_counts"]["count"] = [2, 10**30]
    refused(write(tmp_path, document), "texel_counts.count")


def test_parts_that_are_not_objects_are_refused(tmp_path):
    document = minimal_result()
    document["parts"] = [["door"]]
    refused(write(tmp_path, document), "parts[0]")
    document["parts"] = "door"
    refused(write(tmp_path, document), "parts")


def test_a_folder_where_result_json_belongs_is_refused(tmp_path):
    (tmp_path / "result.json").mkdir()
    with pytest.raises(ufcsr.UfcsrError, match="result.json.*not a regular file"):
        ufcsr.read_result(tmp_path)


def test_a_deeply_nested_study_json_is_refused_naming_it(tmp_path):
    (tmp_path / "study.json").write_text("{" + '"a":{' * 50_000 + "}" * 50_001)
    with pytest.raises(ufcsr.UfcsrError, match="study.json"):
        ufcsr.read_study(tmp_path)


def texel_area_bytes(width, height, values):
    header = b"ufcsr-texel-area/1\n\0" + np.array([width, height], dtype="<u4").tobytes()
    return header + np.asarray(values, dtype="<f4").tobytes()


def test_texel_area_reads_as_float32_of_the_palettes_size(tmp_path):
    path = write(tmp_path, minimal_result())
    (tmp_path / "texel-area.f32").write_bytes(texel_area_bytes(2, 2, [0.0, 1.5, 0.0, 2.25]))
    area = ufcsr.read_result(path).texel_area
    assert area.dtype == np.float32 and area.shape == (4,)
    np.testing.assert_array_equal(area, [0.0, 1.5, 0.0, 2.25])


def test_texel_area_is_checked_as_the_analyzer_checks_it(tmp_path):
    path = write(tmp_path, minimal_result())
    area = tmp_path / "texel-area.f32"
    for data, what in [
        (texel_area_bytes(2, 2, [0.0, 1.0, float("nan"), 0.0]), "texel 2"),
        (texel_area_bytes(2, 2, [0.0, -1.0, 0.0, 0.0]), "texel 1"),
        (texel_area_bytes(4, 1, [0.0] * 4), "4×1 raster"),
        (texel_area_bytes(2, 2, [0.0] * 3), "truncated"),
        (b"not a raster", "not a ufcsr texel-area.f32"),
    ]:
        area.write_bytes(data)
        refused(path, what, read=lambda result: result.texel_area, named=area)
    area.unlink()
    area.mkdir()
    refused(path, "not a regular file", read=lambda result: result.texel_area, named=area)


def test_analyze_leaves_the_figures_out_by_default_with_the_same_tables(program, tmp_path):
    with pytest.warns(ufcsr.UfcsrWarning):
        plain = ufcsr.analyze(EXAMPLE, out=tmp_path / "plain")
    with pytest.warns(ufcsr.UfcsrWarning):
        drawn = ufcsr.analyze(EXAMPLE, out=tmp_path / "drawn", figures=True)
    plain_dir, drawn_dir = plain.path.parent, drawn.path.parent
    assert not (plain_dir / "plots").exists() and not (plain_dir / "frames-strip.png").exists()
    assert not (plain_dir / "map.png").exists() and not (plain_dir / "views.png").exists()
    assert (drawn_dir / "plots").is_dir()
    for name in ["result.json", "parts.csv", "frames.csv", "heatmap.png"]:
        assert (plain_dir / name).read_bytes() == (drawn_dir / name).read_bytes(), name


def test_ctrl_c_late_in_analyze_removes_the_empty_output_folder_it_created(tmp_path):
    # A stand-in for ufcsr-analyze that creates the output folder, then is interrupted (exit 130).
    program = tmp_path / "interrupted-analyze"
    program.write_text('#!/bin/sh\nmkdir -p "$3"\nexit 130\n')
    program.chmod(program.stat().st_mode | stat.S_IXUSR)
    out = tmp_path / "new-out"
    with pytest.raises(KeyboardInterrupt):
        ufcsr.analyze(EXAMPLE, out=out, executable=program)
    assert not os.path.lexists(out)
    # A folder that was there before is left as it was.
    kept = tmp_path / "kept"
    kept.mkdir()
    with pytest.raises(KeyboardInterrupt):
        ufcsr.analyze(EXAMPLE, out=kept, executable=program)
    assert kept.is_dir()
