"""Shared by the tests: where the command-line tools are."""

import os
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture
def cli_binary():
    """`find(name)`: the release binary `name` — `$PENALTY_LAB_<NAME>` (CI sets it to the
    build the isolated test step made), else `target/release/<name>`; skips the test where
    neither exists."""

    def find(name):
        env = "PENALTY_LAB_" + name.upper()
        exe = os.environ.get(env)
        if exe:
            return exe
        cand = ROOT / "target" / "release" / name
        if not cand.exists():
            pytest.skip(f"no {name} binary: cargo build --release --bin {name}, or set {env}")
        return str(cand)

    return find
