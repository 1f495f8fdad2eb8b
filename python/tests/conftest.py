"""Shared fixtures of the Python package's tests: the bundled example archive,
analysed once through ``ufcsr.analyze`` and once by running ``ufcsr-analyze``
directly (the reference). Both need the program: the Rust test harness names
it in UFCSR_ANALYZE_BIN; without it the tests that need it are skipped, and
fail under CI."""

import os
import subprocess
from pathlib import Path

import pytest

import ufcsr

REPOSITORY = Path(__file__).resolve().parents[2]
EXAMPLE = REPOSITORY / "fixtures" / "example"


@pytest.fixture(scope="session")
def program():
    """The ufcsr-analyze the package runs (skipped without one, failed under CI)."""
    try:
        return ufcsr._program.find_program()
    except ufcsr.UfcsrError as error:
        # A skip must not hide a missing program where the suite is meant to be complete.
        if os.environ.get("CI"):
            pytest.fail(f"CI: {error}")
        pytest.skip(str(error))


@pytest.fixture(scope="session")
def example_result(program, tmp_path_factory):
    """The example analysed by ufcsr.analyze, into a fresh folder."""
    out = tmp_path_factory.mktemp("through-python")
    with pytest.warns(ufcsr.UfcsrWarning):
        return ufcsr.analyze(EXAMPLE, out=out)


@pytest.fixture(scope="session")
def cli_result_folder(program, tmp_path_factory):
    """The example analysed by the ufcsr-analyze binary (the reference)."""
    out = tmp_path_factory.mktemp("cli")
    subprocess.run([program, str(EXAMPLE), "--out", str(out), "--quiet"], check=True)
    return out
