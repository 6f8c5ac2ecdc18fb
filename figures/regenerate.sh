#!/usr/bin/env bash
# Regenerates every figure of the repository from data (each binary saves its data first and
# renders from it; --force replaces each folder's previous run whole, keeping its README).
# Run from the repository root: bash figures/regenerate.sh
# The timing figures (runtime_vs_error, cond_cost, engine_scale) measure this machine: run them idle.
# The times below: scripts/budgets.sh (2 cores, idle, 2026-12-07; --optimal-max-n not re-measured).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --bins
cargo run --release --bin sweep -- --force --out figures/sweep
cargo run --release --bin paper_beam -- --force --out figures/paper_beam
cargo run --release --bin deep_drawing -- --force --out figures/deep_drawing
cargo run --release --bin stretch_test -- --force --out figures/stretch_test
cargo run --release --bin stress -- --force --out figures/stress
cargo run --release --bin runtime_vs_error -- --force --out figures/runtime_vs_error
cargo run --release --bin cond_cost -- --force --out figures/cond_cost
cargo run --release --bin cond_accuracy -- --force --out figures/cond_accuracy
cargo run --release --bin solver_cost -- --force --out figures/solver_cost   # 1 min 32 s on 2 cores
cargo run --release --bin solver_cost -- --families hertz-3d --sphere-h0 2 --force --out figures/solver_cost/hertz-3d   # 1 min 19 s
cargo run --release --bin solver_cost -- --families hertz-two-body --force --out figures/solver_cost/hertz-two-body   # 3 min 20 s
cargo run --release --bin contact_bench -- --force --out figures/contact_bench --optimal-max-n 6000   # ≈ 1.6 h on 2 cores
cargo run --release --bin contact_bench -- --cases inclined-15,inclined-30,inclined-45,patch-two-body-mortar,patch-two-body-nts-1,patch-two-body-nts-2,hertz-two-body,hertz-normals --force --out figures/contact_bench/coupled   # ≈ 2.4 min
cargo run --release --bin penalty_scaling -- --force --out figures/penalty_scaling   # ≈ 70 s
cargo run --release --bin friction_bench -- --force --out figures/friction_bench   # ≈ 10 s
cargo run --release --bin friction_bench -- --cases cattaneo-mindlin --force --out figures/friction_bench/cattaneo-mindlin   # 7 min 31 s
cargo run --release --bin engine_scale -- --sizes 10000,100000,1000000 --force --out figures/engine_scale
