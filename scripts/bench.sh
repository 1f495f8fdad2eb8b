#!/usr/bin/env bash
# Throughput benchmark driver: ufcsr vs the decode-only ceiling vs a per-pixel
# hash map (the original algorithm), on the same tiles in one run, with the
# issue's targets: the counting stage by default and with --frames-csv off
# against decode-only, the whole ufcsr analyze process against a whole
# decode-only process, peak memory.
#   scripts/bench.sh                  # a generated realistic archive and a
#                                     # scenario A capture at 60 px/° (ufcsr capture demo)
#   scripts/bench.sh --no-capture     # the generated archive only
#   scripts/bench.sh --frames 6       # a smaller generated archive (default 24 frames, 1,200 tiles)
#   scripts/bench.sh --archive DIR    # your own capture(s) only (repeatable)
#   RAYON_NUM_THREADS=1 scripts/bench.sh
set -euo pipefail
cd "$(dirname "$0")/.."
args=()
capture=1
for arg in "$@"; do
    case "$arg" in
        --no-capture) capture=0 ;;
        --archive|--kernels) capture=0; args+=("$arg") ;;
        *) args+=("$arg") ;;
    esac
done
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# The binaries (ufcsr analyze for the whole-process figures, ufcsr-capture
# for the capture) come from the command-line crate.
cargo build --release -q -p ufcsr-cli --features capture
if [[ $capture == 1 ]]; then
    export XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-$work}"
    "${CARGO_TARGET_DIR:-target}/release/ufcsr-capture" demo --scenario A --out "$work/A" -q > /dev/null
    # The generated archive first, then the capture.
    cargo bench -p ufcsr --bench throughput -- "${args[@]}" --also "$work/A"
else
    cargo bench -p ufcsr --bench throughput -- "${args[@]}"
fi
