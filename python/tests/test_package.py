"""The package itself: pure Python, typed, safe on hostile files, and
interruptible. These tests need no ufcsr-analyze (a stand-in program plays
it where one is run)."""

import inspect
import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

import ufcsr
from ufcsr import _files

PACKAGE = Path(ufcsr.__file__).parent


def test_version_and_type_information_are_there():
    assert ufcsr.__version__ == "0.1.0"
    assert (PACKAGE / "py.typed").is_file()
    assert not list(PACKAGE.glob("*.so")), "no native code: the package installs without a compiler"


def test_every_analysis_option_is_an_explicit_keyword():
    parameters = inspect.signature(ufcsr.analyze).parameters
    assert not any(p.kind is inspect.Parameter.VAR_KEYWORD for p in parameters.values())
    for name in ["pidt", "parts", "fcsp", "palette_size", "background", "dedupe", "trim", "scale", "max",
                 "shard", "mesh", "frames_csv", "threads", "strict", "no_manifest", "progress"]:
        assert parameters[name].kind is inspect.Parameter.KEYWORD_ONLY, name


def fake_program(tmp_path, body):
    """A stand-in ufcsr-analyze: a shell script."""
    program = tmp_path / "fake-ufcsr-analyze"
    program.write_text("#!/bin/sh\n" + textwrap.dedent(body))
    program.chmod(0o755)
    return program


def test_ctrl_c_stops_the_analysis_within_a_second_and_raises(tmp_path):
    started, stopped = tmp_path / "started", tmp_path / "stopped"
    program = fake_program(tmp_path, f"""\
        trap 'touch {stopped}; exit 130' INT
        touch {started}
        sleep 30 & wait
    """)
    script = (
        "import sys, ufcsr\n"
        "try:\n"
        f"    ufcsr.analyze({str(tmp_path)!r}, out={str(tmp_path / 'out')!r}, executable={str(program)!r})\n"
        "except KeyboardInterrupt:\n"
        "    sys.exit(3)\n"
    )
    child = subprocess.Popen([sys.executable, "-c", script])
    deadline = time.monotonic() + 30
    while not started.exists():
        assert time.monotonic() < deadline and child.poll() is None, "the stand-in program never started"
        time.sleep(0.05)
    interrupted = time.monotonic()
    child.send_signal(signal.SIGINT)
    assert child.wait(10) == 3, "KeyboardInterrupt reached the caller"
    assert stopped.exists(), "the program was told to stop (SIGINT) and cleaned up"
    # Generous for a loaded CI machine; the program itself would have run 30 s.
    assert time.monotonic() - interrupted < 5
    assert not (tmp_path / "out").exists()


def test_a_failed_run_raises_its_error_line(tmp_path):
    program = fake_program(tmp_path, """\
        echo "warning: something" >&2
        echo "error: archive.png: not a PNG" >&2
        exit 2
    """)
    with pytest.raises(ufcsr.UfcsrError, match="archive.png: not a PNG"):
        ufcsr.analyze(tmp_path, out=tmp_path / "out", executable=program)


def test_a_missing_program_says_how_to_get_one(tmp_path, monkeypatch):
    monkeypatch.delenv("UFCSR_ANALYZE", raising=False)
    monkeypatch.delenv("UFCSR_ANALYZE_BIN", raising=False)
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(ufcsr.UfcsrError, match="not on PATH.*UFCSR_ANALYZE"):
        ufcsr.analyze(tmp_path)


def write_result(folder, counts, width=4, height=4):
    folder.mkdir(parents=True, exist_ok=True)
    seen = np.flatnonzero(counts)
    document = {
        "schema": "ufcsr-result/1",
        "settings": {"archive": "a", "palette": {"kind": "canonical", "width": width, "height": height}},
        "images": {"found": 1, "failed": 0},
        "grand_total": int(counts.sum()),
        "parts": [],
        "texel_counts": {"encoding": "delta", "texels": int(len(seen)),
                         "texel_delta": np.diff(seen, prepend=0).tolist(), "count": counts[seen].tolist()},
    }
    (folder / "result.json").write_text(json.dumps(document))
    return folder / "result.json", document


def test_texel_counts_are_decoded_in_python(tmp_path):
    counts = np.zeros(16, dtype=np.uint32)
    counts[[0, 3, 15]] = [5, 1, 7]
    path, _ = write_result(tmp_path / "r", counts)
    np.testing.assert_array_equal(ufcsr.read_result(path).texel_counts, counts)


@pytest.mark.parametrize("edit, message", [
    (lambda e: e.update(texels=9), "edited or truncated"),
    (lambda e: e.update(texel_delta=[0, 3, 0]), "once each"),
    (lambda e: e.update(texel_delta=[0, 3, 13]), "outside the palette"),
    (lambda e: e.update(count=[5, 0, 7]), "only seen texels"),
    (lambda e: e.update(encoding="dense"), "delta encoding"),
])
def test_edited_texel_counts_are_refused_naming_the_file(tmp_path, edit, message):
    counts = np.zeros(16, dtype=np.uint32)
    counts[[0, 3, 15]] = [5, 1, 7]
    path, document = write_result(tmp_path / "r", counts)
    edit(document["texel_counts"])
    path.write_text(json.dumps(document))
    with pytest.raises(ufcsr.UfcsrError, match=f"result.json.*{message}"):
        ufcsr.read_result(path).texel_counts


def test_an_unknown_schema_version_is_refused(tmp_path):
    path, document = write_result(tmp_path / "r", np.ones(16, dtype=np.uint32))
    document["schema"] = "ufcsr-result/999"
    path.write_text(json.dumps(document))
    with pytest.raises(ufcsr.UfcsrError, match="version this package does not know"):
        ufcsr.read_result(path)


def test_a_fifo_is_refused_without_hanging(tmp_path):
    fifo = tmp_path / "result.json"
    os.mkfifo(fifo)
    with pytest.raises(ufcsr.UfcsrError, match="not a regular file"):
        ufcsr.read_result(fifo)


def test_a_link_to_a_device_is_refused(tmp_path):
    (tmp_path / "result.json").symlink_to("/dev/zero")
    with pytest.raises(ufcsr.UfcsrError, match="not a regular file"):
        ufcsr.read_result(tmp_path)


def test_files_over_the_size_cap_are_refused(tmp_path, monkeypatch):
    path, _ = write_result(tmp_path / "r", np.ones(16, dtype=np.uint32))
    monkeypatch.setitem(_files.LIMITS, "result", 100)
    with pytest.raises(ufcsr.UfcsrError, match="more than the 100 bytes"):
        ufcsr.read_result(path)


def test_a_half_committed_set_is_refused(tmp_path):
    path, _ = write_result(tmp_path / "r", np.ones(16, dtype=np.uint32))
    (path.parent / ".ufcsr-commit.json").write_text("{}")
    with pytest.raises(ufcsr.UfcsrError, match="part old, part new"):
        ufcsr.read_result(path)


def test_a_frames_csv_fifo_is_refused_naming_it(tmp_path):
    path, _ = write_result(tmp_path / "r", np.ones(16, dtype=np.uint32))
    os.mkfifo(path.parent / "frames.csv")
    with pytest.raises(ufcsr.UfcsrError, match="frames.csv: not a regular file"):
        ufcsr.read_result(path)


def test_the_heatmap_is_never_written_over_its_input_or_a_device(tmp_path):
    path, _ = write_result(tmp_path / "r", np.ones(16, dtype=np.uint32))
    with pytest.raises(ufcsr.UfcsrError, match="not written over its input"):
        ufcsr.heatmap(path.parent, out=path)
    fifo = tmp_path / "pipe.png"
    os.mkfifo(fifo)
    with pytest.raises(ufcsr.UfcsrError, match="not a regular file"):
        ufcsr.heatmap(path.parent, out=fifo)
    assert json.loads(path.read_text())["schema"] == "ufcsr-result/1"


def test_placement_study_and_observer_outputs_read_as_document_and_tables(tmp_path):
    (tmp_path / "placement.json").write_text(json.dumps({"schema": "ufcsr-placement/1", "best": []}))
    (tmp_path / "placement.csv").write_text("name,legible_s\nhood,1.5\ngrill,2.0\n")
    placement = ufcsr.read_placement(tmp_path)
    assert placement.document["schema"] == "ufcsr-placement/1"
    assert list(placement.tables["placement.csv"]["name"]) == ["hood", "grill"]
    (tmp_path / "study.json").write_text(json.dumps({"schema": "ufcsr-placement/1"}))
    with pytest.raises(ufcsr.UfcsrError, match="not a ufcsr study.json"):
        ufcsr.read_study(tmp_path)


def test_observer_displays_read_from_the_document_and_their_table_and_are_absent_without_them(tmp_path):
    legible = {"mean": 1.5, "mean_ci95": [0.5, 2.5], "monte_carlo_half_width": 0.8,
               "resolution_bound": 0.2, "p2_5": 1.0, "p97_5": 2.0}
    candidate = "hood@0.40x0.15@x1.00y0.05z1.20"
    displays = {"display_m": [0.4, 0.15], "spacing_m": 0.3, "sample": 1.0, "interval": "t", "seconds": 3.0,
                "observers": [{"legible_s": {candidate: 2.0}, "coarser_legible_s": None}],
                "summary": [{"candidate": candidate, "kind": "patch", "legible_s": legible}]}
    (tmp_path / "observers.json").write_text(json.dumps({"schema": "ufcsr-observers/1", "displays": displays}))
    (tmp_path / "observer-parts.csv").write_text("part,measure,mean\nhood,angular_area_deg2_s,3.0\n")
    (tmp_path / "observer-displays.csv").write_text(
        "candidate,kind,legible_s_mean,legible_s_ci95_low,legible_s_ci95_high\n"
        f"{candidate},patch,1.5,0.5,2.5\n"
    )
    study = ufcsr.read_observers(tmp_path)
    assert study.document["displays"]["summary"][0]["legible_s"]["mean_ci95"] == [0.5, 2.5]
    assert study.document["displays"]["observers"][0]["legible_s"][candidate] == 2.0
    assert list(study.tables["observer-displays.csv"]["candidate"]) == [candidate]
    assert study.tables["observer-displays.csv"]["legible_s_ci95_high"][0] == 2.5
    (tmp_path / "observer-displays.csv").unlink()
    (tmp_path / "observers.json").write_text(json.dumps({"schema": "ufcsr-observers/1"}))
    older = ufcsr.read_observers(tmp_path)
    assert "displays" not in older.document and "observer-displays.csv" not in older.tables
    assert list(older.tables) == ["observer-parts.csv"]


def test_a_table_pandas_cannot_parse_names_its_file(tmp_path):
    # pandas reads bytes, so its own message named no file.
    path, _ = write_result(tmp_path / "r", np.ones(16, dtype=np.uint32))
    (path.parent / "frames.csv").write_bytes(b'frame,eye\n"0,left\n')
    with pytest.raises(ufcsr.UfcsrError, match=r"frames.csv: not a readable CSV table"):
        ufcsr.read_result(path)
    (tmp_path / "placement.json").write_text(json.dumps({"schema": "ufcsr-placement/2"}))
    (tmp_path / "placement.csv").write_bytes(b"name,legible_s\n\xff\xfe\"hood\n")
    with pytest.raises(ufcsr.UfcsrError, match=r"placement.csv: not a readable CSV table"):
        ufcsr.read_placement(tmp_path)


def test_the_heatmap_is_never_written_through_a_link(tmp_path):
    path, _ = write_result(tmp_path / "r", np.ones(16, dtype=np.uint32))
    elsewhere = tmp_path / "elsewhere.png"
    elsewhere.write_bytes(b"mine")
    link = tmp_path / "heat.png"
    link.symlink_to(elsewhere)
    with pytest.raises(ufcsr.UfcsrError, match="heat.png: exists and is not a regular file"):
        ufcsr.heatmap(path.parent, out=link)
    assert elsewhere.read_bytes() == b"mine" and link.is_symlink()
