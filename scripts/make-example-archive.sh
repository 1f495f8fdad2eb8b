#!/usr/bin/env bash
# Regenerates the synthetic example archive under fixtures/example/
# (108 small tiles, canonical 256×256 palette, 8-part PIdT; ~120 KiB).
set -euo pipefail
cd "$(dirname "$0")/.."
rm -rf fixtures/example
cargo run --release --example make-example-archive -- fixtures/example
