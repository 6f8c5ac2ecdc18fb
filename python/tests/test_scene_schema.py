"""docs/scene.schema.json (the scene format as a JSON Schema, written beside the reader in
src/scene/mod.rs) against the reader itself: every committed scene validates; each change of a
valid scene that the schema refuses, the reader refuses too (ValueError), and each change both
accept stays accepted — so the schema says nothing the reader contradicts."""

import copy
import json
import pathlib

import jsonschema
import pytest

import penalty_lab

ROOT = pathlib.Path(__file__).resolve().parents[2]
SCHEMA = json.loads((ROOT / "docs" / "scene.schema.json").read_text())
VALIDATOR = jsonschema.Draft202012Validator(SCHEMA)
BASE = json.loads((ROOT / "tests" / "data" / "scenes" / "small.scene.json").read_text())


def committed_scenes():
    return sorted(
        p
        for p in ROOT.rglob("*.scene.json")
        if not any(part in ("target", ".git") or part.startswith(".") for part in p.relative_to(ROOT).parts)
    )


def test_the_schema_is_a_valid_draft_2020_12_schema():
    jsonschema.Draft202012Validator.check_schema(SCHEMA)


def test_every_committed_scene_validates():
    scenes = committed_scenes()
    assert len(scenes) >= 20
    for path in scenes:
        errors = list(VALIDATOR.iter_errors(json.loads(path.read_text())))
        assert not errors, f"{path.relative_to(ROOT)}: {errors[0].message}"


def changed(edit):
    scene = copy.deepcopy(BASE)
    edit(scene)
    return scene


def set_key(keys, value):
    def edit(scene):
        target = scene
        for k in keys[:-1]:
            target = target[k]
        target[keys[-1]] = value

    return edit


def drop_key(keys):
    def edit(scene):
        target = scene
        for k in keys[:-1]:
            target = target[k]
        del target[keys[-1]]

    return edit


REFUSED = {
    "no name": drop_key(["name"]),
    "no load": drop_key(["load"]),
    "name a number": set_key(["name"], 3),
    "stiffness with both keys": set_key(["stiffness", "matrix_market"], "K.mtx"),
    "stiffness with an unknown key": set_key(["stiffness", "sparse"], []),
    "stiffness an array": set_key(["stiffness"], [[1.0]]),
    "load a string": set_key(["load"], "0 0 0"),
    "a load entry a string": set_key(["load", 1], "1"),
    "unknown kind": set_key(["constraints", 0, "kind"], "equal"),
    "constraint with dof and terms": set_key(["constraints", 0, "terms"], [[1, 1.0]]),
    "constraint with neither dof nor terms": drop_key(["constraints", 0, "dof"]),
    "negative dof": set_key(["constraints", 0, "dof"], -1),
    "a term of three entries": set_key(["constraints", 0], {"terms": [[1, 1.0, 2.0]], "limit": 0, "kind": "lower"}),
    "a term of one entry": set_key(["constraints", 0], {"terms": [[1]], "limit": 0, "kind": "lower"}),
    "limit missing": drop_key(["constraints", 0, "limit"]),
    "constraints an object without a file": set_key(["constraints"], {"limits": [0.0], "kind": "lower"}),
    "rows with kind and kinds": set_key(
        ["constraints"], {"matrix_market": "D.mtx", "limits": [0.0], "kind": "lower", "kinds": ["lower"]}
    ),
    "rows with an unknown key": set_key(
        ["constraints"], {"matrix_market": "D.mtx", "limits": [0.0], "kind": "lower", "rows": 1}
    ),
    "nodes with an unknown key": set_key(
        ["nodes"], {"coordinates": [[0, 0], [1, 0], [2, 0]], "dofs_per_node": 1, "colour": "red"}
    ),
    "nodes without dofs_per_node": set_key(["nodes"], {"coordinates": [[0, 0], [1, 0], [2, 0]]}),
    "near_null_space with an unknown key": set_key(["near_null_space"], {"matrix_market": "B.mtx", "k": 6}),
}

ACCEPTED = {
    "as committed": lambda s: None,
    "no optional key": lambda s: [s.pop(k) for k in ("description", "units", "meta", "comment")],
    "null description": set_key(["description"], None),
    "no constraints": set_key(["constraints"], []),
    "a coupled row": set_key(["constraints", 0], {"terms": [[0, 1.0], [1, -0.5]], "limit": 0.1, "kind": "upper"}),
    "an integral number as a DOF": set_key(["constraints", 0, "dof"], 1.0),
    "meta of any shape": set_key(["meta"], [1, {"a": None}]),
    "nodes with cells": set_key(
        ["nodes"], {"coordinates": [[0, 0], [1, 0], [2, 0]], "dofs_per_node": 1, "cells": [[0, 1], [1, 2]]}
    ),
}


def reads(scene, tmp_path):
    path = tmp_path / "edited.scene.json"
    path.write_text(json.dumps(scene))
    try:
        penalty_lab.read_scene(path)
    except ValueError as e:
        return str(e)
    return None


@pytest.mark.parametrize("name", sorted(REFUSED))
def test_what_the_schema_refuses_the_reader_refuses(name, tmp_path):
    scene = changed(REFUSED[name])
    assert not VALIDATOR.is_valid(scene), f"{name}: the schema accepts it"
    assert reads(scene, tmp_path) is not None, f"{name}: the reader accepts it"


@pytest.mark.parametrize("name", sorted(ACCEPTED))
def test_what_the_schema_accepts_the_reader_reads(name, tmp_path):
    scene = changed(ACCEPTED[name])
    errors = list(VALIDATOR.iter_errors(scene))
    assert not errors, f"{name}: {errors[0].message}"
    assert reads(scene, tmp_path) is None, f"{name}: {reads(scene, tmp_path)}"
