"""The notebook-style example in python/README.md runs as written."""

import os
import re
import warnings

import ufcsr
from conftest import REPOSITORY


def test_the_readme_example_runs(program, tmp_path, monkeypatch):
    text = (REPOSITORY / "python" / "README.md").read_text()
    block = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    # Run from the repository root as the README says, with the outputs in a scratch folder.
    monkeypatch.chdir(REPOSITORY)
    block = block.replace('out="results"', f"out={str(tmp_path / 'results')!r}")
    block = block.replace('"heatmap-log.png"', repr(str(tmp_path / "heatmap-log.png")))
    block = block.replace('read_result("results")', f"read_result({str(tmp_path / 'results')!r})")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ufcsr.UfcsrWarning)
        exec(compile(block, "python/README.md", "exec"), {})
    assert (tmp_path / "heatmap-log.png").is_file()
    assert os.path.isfile(tmp_path / "results" / "result.json")
