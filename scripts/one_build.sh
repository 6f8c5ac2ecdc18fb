#!/usr/bin/env bash
# One build for the README's two commands: the `penalty_lab` library artifact that
# `cargo build --release --bins` (what `cargo run --release --bin sweep` builds) produces is
# the one `cargo test --release` links (the same file name, whose hash covers the features of
# every dependency). Run from the repository root; CI runs it before the test suite, so the
# builds it makes are the ones the tests reuse.
set -euo pipefail
lib_artifact() {
    python3 -c '
import json, sys
names = set()
for line in sys.stdin:
    try:
        m = json.loads(line)
    except ValueError:
        continue
    if m.get("reason") == "compiler-artifact" and m["target"]["name"] == "penalty_lab" \
            and "lib" in m["target"]["kind"] and not m["profile"]["test"]:
        names.update(f for f in m["filenames"] if f.endswith(".rlib"))
print(" ".join(sorted(names)))'
}
bins=$(cargo build --release --bins --message-format=json | lib_artifact)
tests=$(cargo test --release --no-run --message-format=json | lib_artifact)
echo "library of the binaries: $bins"
echo "library the tests link:  $tests"
if [ -z "$bins" ] || [ "$bins" != "$tests" ]; then
    echo "one_build: the two README commands build the library twice" >&2
    exit 1
fi
echo "one_build: one library build for both README commands"
