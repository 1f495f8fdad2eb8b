"""Bad input gives a clear Python exception naming the file or the option."""

import pytest

import ufcsr
from conftest import EXAMPLE


def test_missing_archive_raises_ufcsr_error_naming_the_path(program, tmp_path):
    missing = tmp_path / "no-such-archive"
    with pytest.raises(ufcsr.UfcsrError, match="no-such-archive"):
        ufcsr.analyze(missing, out=tmp_path / "out")
    assert not (tmp_path / "out" / "result.json").exists()


def test_unknown_option_raises_type_error_naming_it(tmp_path):
    # Every option is an explicit keyword argument (help() and editors list them).
    with pytest.raises(TypeError, match="pidtt"):
        ufcsr.analyze(EXAMPLE, out=tmp_path, pidtt="pidt.png")


def test_option_of_the_wrong_type_raises_type_error(tmp_path):
    with pytest.raises(TypeError, match="threads"):
        ufcsr.analyze(EXAMPLE, out=tmp_path, threads="two")
    with pytest.raises(TypeError, match="strict"):
        ufcsr.analyze(EXAMPLE, out=tmp_path, strict="yes")


def test_bad_option_value_raises_the_analyzers_message(program, tmp_path):
    with pytest.raises(ufcsr.UfcsrError, match="dedupe"):
        ufcsr.analyze(EXAMPLE, out=tmp_path, dedupe="sometimes")
    with pytest.raises(ufcsr.UfcsrError, match="max must be at least 1"):
        ufcsr.analyze(EXAMPLE, out=tmp_path, max=0)
    with pytest.raises(ValueError, match="exclude each other"):
        ufcsr.analyze(EXAMPLE, out=tmp_path, fcsp="palette.png", palette_size="512x512")


def test_missing_pidt_raises_ufcsr_error_naming_it(program, tmp_path):
    with pytest.raises(ufcsr.UfcsrError, match="missing-pidt.png"):
        ufcsr.analyze(EXAMPLE, out=tmp_path, pidt=tmp_path / "missing-pidt.png")


def test_reading_a_missing_or_foreign_result_names_the_file(tmp_path):
    with pytest.raises(ufcsr.UfcsrError, match="result.json"):
        ufcsr.read_result(tmp_path)
    foreign = tmp_path / "other.json"
    foreign.write_text('{"hello": 1}')
    with pytest.raises(ufcsr.UfcsrError, match="other.json.*not a ufcsr result"):
        ufcsr.read_result(foreign)
