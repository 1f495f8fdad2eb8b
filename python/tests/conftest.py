"""Shared fixtures of the Python package's tests: the bundled example archive,
analysed once in-process, and (when the Rust test harness names the binary in
UFCSR_ANALYZE_BIN) once by `ufcsr-analyze` itself, the reference."""

import os
import subprocess
from pathlib import Path

import pytest

import ufcsr

REPOSITORY = Path(__file__).resolve().parents[2]
EXAMPLE = REPOSITORY / "fixtures" / "example"


@pytest.fixture(scope="session")
def example_result(tmp_path_factory):
    """The example analysed by ufcsr.analyze, into a fresh folder."""
    out = tmp_path_factory.mktemp("in-process")
    with pytest.warns(ufcsr.UfcsrWarning):
        return ufcsr.analyze(EXAMPLE, out=out)


@pytest.fixture(scope="session")
def cli_result_folder(tmp_path_factory):
    """The example analysed by the ufcsr-analyze binary (the reference)."""
    binary = os.environ.get("UFCSR_ANALYZE_BIN")
    if not binary:
        # A skip must not hide a missing reference where the suite is meant to be complete.
        if os.environ.get("CI"):
            pytest.fail("CI: UFCSR_ANALYZE_BIN is not set (run through `cargo test`)")
        pytest.skip("UFCSR_ANALYZE_BIN is not set: no ufcsr-analyze to compare with")
    out = tmp_path_factory.mktemp("cli")
    subprocess.run([binary, str(EXAMPLE), "--out", str(out), "--quiet"], check=True)
    return out
