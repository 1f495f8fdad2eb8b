"""The notebook-style example in python/README.md runs as written."""

import os
import re
import tempfile
import warnings

import ufcsr
from conftest import REPOSITORY


def test_the_readme_example_runs(program, tmp_path, monkeypatch):
    text = (REPOSITORY / "python" / "README.md").read_text()
    block = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    # Run from the repository root as the README says, as written: its outputs must land in the
    # scratch folder it makes (here under tmp_path), none in the repository.
    monkeypatch.chdir(REPOSITORY)
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    before = set(os.listdir(REPOSITORY))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ufcsr.UfcsrWarning)
        exec(compile(block, "python/README.md", "exec"), {})
    assert set(os.listdir(REPOSITORY)) == before, "the README example wrote into the repository"
    (scratch,) = list(tmp_path.glob("ufcsr-example-*"))
    assert (scratch / "heatmap-log.png").is_file()
    assert (scratch / "results" / "result.json").is_file()
