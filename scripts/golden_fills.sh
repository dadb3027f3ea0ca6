#!/usr/bin/env bash
# Fills every reference and cloth case of the shared data at the defaults, one
# thread, and writes the outputs' checksums and the reports' figures, so that
# two builds can be compared for "the same results to the last digit":
#
#   bash scripts/golden_fills.sh build-before /tmp/before
#   bash scripts/golden_fills.sh build-after /tmp/after
#   diff /tmp/before/md5.txt /tmp/after/md5.txt && diff /tmp/before/figures.txt /tmp/after/figures.txt
#
# FOLDFILL_SHARED names the shared data folder (default: ../shared beside the
# source folder).
set -euo pipefail
cd "$(dirname "$0")/.."
build=$(realpath "${1:?usage: golden_fills.sh BUILD_DIR OUT_DIR}")
out=${2:?usage: golden_fills.sh BUILD_DIR OUT_DIR}
shared=${FOLDFILL_SHARED:-../shared}
[[ -d "$shared/data" ]] || { echo "golden_fills.sh: no shared data at $shared" >&2; exit 3; }
mkdir -p "$out"
out=$(realpath "$out")
: > "$out/rc.txt"
for f in "$shared"/data/reference/*_hole.obj "$shared"/data/cloth/*_hole.obj; do
  n=$(basename "$f" .obj)
  rc=0
  OMP_NUM_THREADS=1 "$build/foldfill" fill "$f" -o "$out/$n.obj" --report "$out/$n.json" --quiet \
    || rc=$?
  echo "$n rc=$rc" >> "$out/rc.txt"
done
(cd "$out" && md5sum ./*.obj > md5.txt)
/usr/bin/python3 - "$out" <<'PY' > "$out/figures.txt"
import glob, json, os, sys
for path in sorted(glob.glob(os.path.join(sys.argv[1], "*.json"))):
    for hole in json.load(open(path)).get("holes", []):
        print(os.path.basename(path), hole.get("method"), hole.get("iterations"),
              json.dumps(hole.get("energy"), sort_keys=True), hole.get("crossings"),
              hole.get("stop_reason"))
PY
echo "wrote $out/md5.txt and $out/figures.txt"
