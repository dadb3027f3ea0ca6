#!/usr/bin/env bash
# Sets up, builds and runs the built-in example: writes out/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
./build/foldfill demo "${1:-out/demo}"
