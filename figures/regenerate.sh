#!/usr/bin/env bash
# Regenerates every figure of the repository from data (each binary saves its data first and
# renders from it). Run from the repository root: bash figures/regenerate.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo run --release --bin sweep -- --out figures/sweep
cargo run --release --bin paper_beam -- --out figures/paper_beam
