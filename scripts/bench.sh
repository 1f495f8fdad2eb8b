#!/usr/bin/env bash
# Throughput benchmark driver: ufcsr vs the decode-only ceiling vs a per-pixel
# hash map (the original algorithm), on the same tiles in one run.
#   scripts/bench.sh                  # generated realistic archive, all cores
#   scripts/bench.sh --frames 6       # bigger generated archive
#   scripts/bench.sh --archive DIR    # your own capture
#   RAYON_NUM_THREADS=1 scripts/bench.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo bench --bench throughput -- "$@"
