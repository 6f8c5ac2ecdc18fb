"""The worked example a Python user copies: Hertz in scikit-fem, every rule through
penalty_lab.solve, p0 within 3 % of Hertz's (the example's own exit status)."""

import pathlib
import runpy

import pytest

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"


def test_skfem_hertz_reproduces_hertz_p0_within_3_percent(capsys):
    pytest.importorskip("skfem")
    example = runpy.run_path(str(EXAMPLES / "skfem_hertz.py"))
    assert example["main"]() == 0
    out = capsys.readouterr().out
    assert out.count("| vertical |") == 8 and out.count("| normal |") == 8, out
    assert "failed" not in out
