#!/usr/bin/env bash
# The batch recipe (scripts/batch_parallel.sh): 20 generated sheets filled by
# GNU parallel with 2 jobs give the same meshes, byte for byte, and the same
# per-file outcomes as one process of the CLI's batch mode over them.
#   test_batch_parallel.sh FOLDFILL_CLI
set -euo pipefail
cli=$1
root=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

python3 "$root/tests/tools/make_sheets.py" "$work/in" 20
ls "$work"/in/*.obj > "$work/list.txt"
[ "$(wc -l < "$work/list.txt")" -eq 20 ]

# One process over the whole list.
"$cli" fill $(cat "$work/list.txt") -o "$work/single" --report "$work/single.json" --quiet

fail=0
for per_run in 1 3; do
  out=$work/parallel_$per_run
  FOLDFILL=$cli OMP_NUM_THREADS=1 bash "$root/scripts/batch_parallel.sh" -j 2 -n "$per_run" \
    "$work/list.txt" "$out"
  for file in "$work"/single/*.obj; do
    if ! cmp -s "$file" "$out/$(basename "$file")"; then
      echo "FAIL: -n $per_run: $(basename "$file") differs from the one-process output"
      fail=1
    fi
  done
  python3 - "$work/single.json" "$out/report.json" <<'PY' || fail=1
import json, sys
single, merged = (json.load(open(p)) for p in sys.argv[1:])
outcome = lambda report: [(f["input"], f["status"], f["filled_loops"]) for f in
                          sorted(report["files"], key=lambda f: f["input"])]
assert len(merged["files"]) == 20, len(merged["files"])
assert outcome(single) == outcome(merged), (outcome(single), outcome(merged))
assert merged["totals"] == single["totals"] == {"filled": 20, "unchanged": 0, "failed": 0}, \
    merged["totals"]
PY
done

# A file that cannot be read: reported as failed, exit code 11, the others written.
echo "$work/in/missing.obj" >> "$work/list.txt"
status=0
FOLDFILL=$cli bash "$root/scripts/batch_parallel.sh" -j 2 "$work/list.txt" "$work/bad" \
  2>/dev/null || status=$?
if [ "$status" -ne 11 ]; then echo "FAIL: exit code $status with a missing file, not 11"; fail=1; fi
python3 - "$work/bad/report.json" <<'PY' || fail=1
import json, sys
report = json.load(open(sys.argv[1]))
assert report["totals"] == {"filled": 20, "unchanged": 0, "failed": 1}, report["totals"]
PY

if ((fail)); then echo "0 passed, 1 failed"; exit 1; fi
echo "batch recipe: 20 files, parallel -j 2 gives the one-process outputs"
