#!/usr/bin/env bash
# Runs every command whose run time the docs state (scripts/budgets.tsv) and prints the
# measured wall time beside the stated one. Run from the repository root on an idle machine:
#
#   bash scripts/budgets.sh              every command stated at ≤ 10 min (≈ 45 min in all)
#   bash scripts/budgets.sh --all        also the longer one (contact_bench --optimal-max-n 6000, ≈ 1.6 h)
#   bash scripts/budgets.sh NAME...      the named rows only (first column of the table)
#
# Each command writes into a fresh temporary folder (removed afterwards) through the release
# binaries, built first. A row is "ok" when measured ≤ 1.5 × stated (and ≥ stated / 1.5: a time
# that has fallen that far is stale too); exit status 1 if any row is not. Its lines are what
# the docs should state; update budgets.tsv with them (tests/architecture.rs then names every
# document that still states the old time).
set -euo pipefail
cd "$(dirname "$0")/.."

ALL=0
ONLY=()
for a in "$@"; do
    case "$a" in
    --all) ALL=1 ;;
    -h | --help)
        sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'
        exit 0
        ;;
    -*)
        echo "budgets: unknown flag $a (see --help)" >&2
        exit 2
        ;;
    *) ONLY+=("$a") ;;
    esac
done
if [ "${#ONLY[@]}" -gt 0 ]; then
    for n in "${ONLY[@]}"; do
        if ! grep -q "^${n}	" scripts/budgets.tsv; then
            echo "budgets: no row named $n in scripts/budgets.tsv" >&2
            exit 2
        fi
    done
fi

cargo build --release --bins
BIN="${CARGO_TARGET_DIR:-$PWD/target}/release"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT

printf '%-28s %12s %12s %7s  %s\n' name stated measured ratio verdict
FAILED=0
while IFS=$'\t' read -r name seconds stated _where command; do
    case "$name" in '#'* | '') continue ;; esac
    if [ "${#ONLY[@]}" -gt 0 ]; then
        [[ " ${ONLY[*]} " == *" $name "* ]] || continue
    elif [ "$ALL" != 1 ] && awk -v s="$seconds" 'BEGIN { exit !(s > 600) }'; then
        printf '%-28s %12s %12s %7s  %s\n' "$name" "$stated" - - "skipped (--all)"
        continue
    fi
    out="$TMP/$name"
    read -r -a argv <<<"${command//\{out\}/$out}"
    log="$TMP/$name.log"
    t0=$(date +%s.%N)
    rc=0
    "$BIN/${argv[0]}" "${argv[@]:1}" --quiet >"$log" 2>&1 || rc=$?
    if [ "$rc" = 0 ]; then
        t1=$(date +%s.%N)
        read -r measured ratio verdict < <(awk -v a="$t0" -v b="$t1" -v s="$seconds" 'BEGIN {
            m = b - a; r = m / s
            v = (r <= 1.5 && r >= 1 / 1.5) ? "ok" : (r > 1.5 ? "SLOWER" : "FASTER")
            printf "%.1f %.2f %s\n", m, r, v }')
        [ "$verdict" = ok ] || FAILED=1
        printf '%-28s %12s %11ss %7s  %s\n' "$name" "$stated" "$measured" "$ratio" "$verdict"
    else
        FAILED=1
        printf '%-28s %12s %12s %7s  %s\n' "$name" "$stated" - - "FAILED (exit $rc): $(tail -1 "$log")"
    fi
    rm -rf "$out"
done <scripts/budgets.tsv
exit "$FAILED"
