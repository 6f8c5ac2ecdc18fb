#!/usr/bin/env python3
"""Builds the fixed cond2 panel of tests/data/cond_reference/ (read by tests/verification/cond_reference.rs).

Each case is a stored matrix -- K of a scene, K + D E D^T for the penalties `solve --json`
prints, or the saddle point [K D; D^T 0] of lagrange's active DOFs -- written as Matrix
Market (every entry with 17 significant digits, so it reads back bit for bit), and its
reference sigma_max, sigma_min and cond2 from scripts/cond_reference.py (python-flint ball
arithmetic, mpmath at 40 digits where Arb cannot isolate clustered eigenvalues): values from
outside this project's code, for the same stored matrix.

    cargo build --release --bin solve --bin sweep
    target/release/sweep --families beam,membrane --count 8 --seed 11 --eps 1:1e11:3 \
        --methods constant --metrics none --no-figures --quiet --out /tmp/panel-run \
        --write-scenes /tmp/panel-scenes
    python3 scripts/cond_panel.py /tmp/panel-scenes tests/data/cond_reference

Takes ≈ 10 minutes (the 300+-unknown references dominate).
"""

import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
import cond_reference as cr  # noqa: E402

SOLVE = os.path.join(ROOT, "target", "release", "solve")

# (case name, scene, solve arguments or None for K alone, saddle point?)
CASES = [
    ("beam0000-K", "beam-0000", None, False),
    ("beam0000-eps1e11", "beam-0000", ["--method", "constant", "--eps", "1e11"], False),
    ("beam0002-eps1", "beam-0002", ["--method", "constant", "--eps", "1"], False),
    ("beam0003-eps1e6", "beam-0003", ["--method", "constant", "--eps", "1e6"], False),
    ("beam0005-eps1e11", "beam-0005", ["--method", "constant", "--eps", "1e11"], False),
    ("beam0007-scaled1", "beam-0007", ["--method", "scaled", "--factor", "1"], False),
    ("beam0001-eps1e11-dense", "beam-0001", ["--method", "constant", "--eps", "1e11"], False),
    ("beam0006-K-dense", "beam-0006", None, False),
    ("membrane0005-K", "membrane-0005", None, False),
    ("membrane0005-eps1e11", "membrane-0005", ["--method", "constant", "--eps", "1e11"], False),
    ("membrane0003-scaled1", "membrane-0003", ["--method", "scaled", "--factor", "1"], False),
    ("beam0000-lagrange", "beam-0000", ["--method", "lagrange"], True),
    ("membrane0005-lagrange", "membrane-0005", ["--method", "lagrange"], True),
    # The committed elasticity scenes (tests/data/elasticity/, from scikit-fem): saddle points
    # whose negative eigenvalues cluster within 0.1 % (conditioning::saddle::schur).
    ("elasticity-quad-block-lagrange", "elasticity-quad-block", ["--method", "lagrange"], True),
    ("elasticity-tet-brick-lagrange", "elasticity-tet-brick", ["--method", "lagrange"], True),
]

# Scenes read from the repository instead of the generated folder.
COMMITTED = os.path.join(ROOT, "tests", "data", "elasticity")

# Largest matrix Arb encloses (the 527-unknown saddle point takes ≈ 3 minutes); larger ones go
# to mpmath.
ARB_MAX_N = 600


def write_mtx(path, a, comment):
    n = len(a)
    entries = [(i, j, a[i][j]) for j in range(n) for i in range(j, n) if a[i][j] != 0.0]
    with open(path, "w") as f:
        f.write("%%MatrixMarket matrix coordinate real symmetric\n")
        f.write(f"% {comment}\n")
        f.write(f"{n} {n} {len(entries)}\n")
        for i, j, v in entries:
            f.write(f"{i + 1} {j + 1} {v!r}\n")


def main():
    scenes, out = sys.argv[1], sys.argv[2]
    os.makedirs(out, exist_ok=True)
    panel = []
    for name, scene, args, saddle in CASES:
        folder = COMMITTED if scene.startswith("elasticity-") else scenes
        path = os.path.join(folder, scene + ".scene.json")
        sc, a = cr.read_scene(path)
        n = len(a)
        entry = {"case": name, "scene": scene, "n": n}
        if args:
            v = json.loads(subprocess.check_output([SOLVE, path, *args, "--json"]))
            if saddle:
                active = v["system"]["saddle_point"]["active"]
                dofs = [sc["constraints"][c]["dof"] for c in active]
                entry["saddle_dofs"] = dofs
                m = len(dofs)
                big = [[0.0] * (n + m) for _ in range(n + m)]
                for i in range(n):
                    big[i][:n] = a[i]
                for c, d in enumerate(dofs):
                    big[d][n + c] = big[n + c][d] = 1.0
                matrix, stored = big, a
            else:
                for c, e in zip(sc["constraints"], v["penalties"]):
                    if e:
                        a[c["dof"]][c["dof"]] = a[c["dof"]][c["dof"]] + float(e)
                matrix = stored = a
            entry["solve"] = args
        else:
            matrix = stored = a
        mtx = name + ".mtx"
        write_mtx(os.path.join(out, mtx), stored, f"{name}: from {scene} ({' '.join(args or ['K'])})")
        entry["matrix"] = mtx
        balls = cr.enclose(matrix) if len(matrix) <= ARB_MAX_N else None
        if balls is not None:
            smax, smin = balls
            engine = "python-flint (Arb) 256 bits, rigorous balls"
        else:
            smax, smin = cr.eigsy_40(matrix)
            engine = "mpmath eigsy, 40 digits"
        entry.update(
            engine=engine,
            sigma_max=cr.dec(smax),
            sigma_min=cr.dec(smin),
            cond2=cr.dec(smax / smin),
        )
        print(name, entry["n"], entry["cond2"], engine, flush=True)
        panel.append(entry)
    with open(os.path.join(out, "panel.json"), "w") as f:
        json.dump({"generated_by": "scripts/cond_panel.py", "cases": panel}, f, indent=1)
        f.write("\n")


if __name__ == "__main__":
    main()
