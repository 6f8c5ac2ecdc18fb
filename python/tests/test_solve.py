"""penalty_lab.solve against the command-line tool `solve --json` on the committed scenes:
the same record, key for key and bit for bit (the timings aside), from arrays handed in
through Python (read_scene → SciPy matrices → solve)."""

import json
import pathlib
import subprocess

import numpy as np
import pytest
import scipy.sparse as sp

import penalty_lab

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCENES = ["bed_cantilever.scene.json", "paper_beam.scene.json"]
CASES = [
    ("condensed", {"delta": 1e-4}, ["--delta", "1e-4"]),
    ("constant", {"eps": 1e6}, ["--eps", "1e6"]),
    ("paper", {"delta": 1e-4}, ["--delta", "1e-4"]),
    ("lagrange", {}, []),
    ("augmented", {}, []),
]


def _timing(key):
    return "seconds" in key  # seconds, seconds_direct, pcg_seconds_ic0, *_to_err_seconds, …


@pytest.mark.parametrize("scene", SCENES)
@pytest.mark.parametrize("method, knobs, flags", CASES)
def test_rows_equal_the_command_line_tools(scene, method, knobs, flags, cli_binary):
    exe = cli_binary("solve")
    path = ROOT / "scenes" / scene
    cli = json.loads(
        subprocess.run([exe, str(path), "--method", method, *flags, "--json"], check=True,
                       capture_output=True, text=True).stdout
    )
    s = penalty_lab.read_scene(path)
    py = penalty_lab.solve(s["K"], s["q"], s["D"], s["limits"], s["kinds"], method, name=s["name"], **knobs)
    assert sorted(py) == sorted(cli)
    for key in cli:
        if not _timing(key):
            assert py[key] == cli[key], key


def test_a_hand_built_problem_matches_its_closed_form():
    # Two springs in series, k = 1: K = [[2, -1], [-1, 1]], a load 1 on DOF 1 pushing it past
    # an obstacle at u1 ≤ 0.5. Lagrange: u1 = 0.5, u0 = 0.25, the contact force r = q1 − (K u)1
    # = 1 − (−0.25 + 0.5) = 0.75.
    K = sp.csr_matrix(np.array([[2.0, -1.0], [-1.0, 1.0]]))
    r = penalty_lab.solve(K, [0.0, 1.0], np.array([[0.0, 1.0]]), [0.5], ["upper"], "lagrange")
    assert r["u"] == pytest.approx([0.25, 0.5], abs=1e-15)
    assert r["forces"] == pytest.approx([0.75], abs=1e-15)
    c = penalty_lab.solve(K, [0.0, 1.0], sp.csr_matrix([[0.0, 1.0]]), [0.5], ["upper"], "condensed", delta=1e-3)
    assert c["max_penetration"] == pytest.approx(1e-3, rel=1e-9)


@pytest.mark.parametrize(
    "change, message",
    [
        ({"q": [0.0, np.nan]}, "load entry 1 is not finite"),
        ({"D": np.array([[np.nan, 1.0]])}, "constraint 0"),
        ({"q": [0.0, 1.0, 2.0]}, r"load vector q \(K is 2×2\) has 3 entries, expected 2"),
        ({"kinds": ["sideways"]}, "kind"),
        ({"kinds": []}, "kinds"),
        ({"method": "magic"}, "magic"),
        ({"D": np.array([[0.0, 1.0, 0.0]])}, "columns"),
        ({"limits": [np.inf]}, "finite|limit"),
    ],
)
def test_bad_input_raises_value_error(change, message):
    args = {"K": np.array([[2.0, -1.0], [-1.0, 1.0]]), "q": [0.0, 1.0], "D": np.array([[0.0, 1.0]]),
            "limits": [0.5], "kinds": ["upper"], "method": "lagrange"}
    args.update(change)
    with pytest.raises(ValueError, match=message):
        penalty_lab.solve(**args)


def test_a_missing_knob_raises_value_error():
    with pytest.raises(ValueError, match="delta|δ"):
        penalty_lab.solve(np.eye(2), [0.0, 1.0], np.array([[0.0, 1.0]]), [0.5], ["upper"], "condensed")
