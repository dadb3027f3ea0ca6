#!/usr/bin/env bash
# Fills the mesh files of a list with GNU parallel, on one machine or over
# ssh on several (README, "Past one machine"). Each run of the CLI's batch
# mode takes a chunk of the list and writes its outputs into OUTDIR and its
# batch report into OUTDIR/reports/; the reports are then merged into
# OUTDIR/report.json (scripts/merge_reports.py).
#
#   scripts/batch_parallel.sh [-j JOBS] [-n FILES_PER_RUN] LIST OUTDIR [fill options...]
#
# LIST: one mesh path a line (blank lines and lines starting with # skipped).
# JOBS: runs at the same time (default: the core count); each run fills its
# files one after the other with the holes of a file in parallel, so set
# OMP_NUM_THREADS=1 with JOBS = the core count for many small files.
# FILES_PER_RUN: files per run of the CLI (default 1). The fill options are
# passed to every run (e.g. --holes all --lambda 0.001); -o and --report are
# this script's. The CLI is $FOLDFILL, else `foldfill` on PATH, else
# build/foldfill. Extra options for GNU parallel go in $PARALLEL (its own
# variable), e.g. PARALLEL="--sshloginfile nodes --workdir ." to spread the
# runs over machines that see the same files.
#
# Exit code: 0 when every file was filled or had nothing to fill; 11 when
# some file failed or was only partly filled (its outputs are written as far
# as they go; see the report); another CLI exit code when a run could not
# start (a bad option, an unwritable folder).
set -euo pipefail

jobs=$(nproc)
per_run=1
while getopts "j:n:" option; do
  case $option in
    j) jobs=$OPTARG ;;
    n) per_run=$OPTARG ;;
    *) echo "usage: $0 [-j JOBS] [-n FILES_PER_RUN] LIST OUTDIR [fill options...]" >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
if (($# < 2)); then
  echo "usage: $0 [-j JOBS] [-n FILES_PER_RUN] LIST OUTDIR [fill options...]" >&2
  exit 2
fi
list=$1 out_dir=$2
shift 2

here=$(cd "$(dirname "$0")" && pwd)
cli=${FOLDFILL:-}
if [ -z "$cli" ]; then
  if command -v foldfill >/dev/null; then cli=$(command -v foldfill); else cli=$here/../build/foldfill; fi
fi
command -v parallel >/dev/null || { echo "$0: GNU parallel is not installed (Debian: parallel)" >&2; exit 2; }
[ -r "$list" ] || { echo "$0: $list: cannot read the file list" >&2; exit 3; }

mkdir -p "$out_dir/reports"
rm -f "$out_dir"/reports/part-*.json
# {#} numbers the runs; -X puts up to FILES_PER_RUN paths on each command line.
status=0
grep -v -e '^[[:space:]]*$' -e '^[[:space:]]*#' "$list" | sed 's/^[[:space:]]*//; s/[[:space:]]*$//' |
  parallel --will-cite --jobs "$jobs" -X -N "$per_run" --halt never \
    "$cli" fill {} -o "$out_dir" --report "$out_dir/reports/part-{#}.json" --quiet "$@" ||
  status=$?

python3 "$here/merge_reports.py" -o "$out_dir/report.json" --list "$list" \
  "$out_dir"/reports/part-*.json
# parallel's status is the number of failed runs (101 and above: more, or
# its own error): report a batch with failures like the CLI's batch mode.
if ((status != 0)); then
  python3 - "$out_dir/report.json" <<'PY' && exit 11
import json, sys
sys.exit(0 if json.load(open(sys.argv[1]))["totals"]["failed"] > 0 else 1)
PY
  exit "$status"
fi
