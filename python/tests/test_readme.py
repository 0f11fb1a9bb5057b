"""The README's examples run as written."""

import os
import re

import pytest

from conftest import ROOT

README = (ROOT / "python" / "README.md").read_text()
BLOCKS = re.findall(r"```python\n(.*?)```", README, re.S)


def test_readme_usage_runs(monkeypatch, capsys):
    monkeypatch.chdir(ROOT)  # it names data/scenes/phantom.toml
    exec(compile(BLOCKS[0], "README usage", "exec"), {})
    assert "alpha_max" in capsys.readouterr().out.lower()


def test_readme_figure_runs(tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    exec(compile(BLOCKS[1], "README figure", "exec"), {})
    assert os.path.getsize(tmp_path / "fig5.png") > 10_000
