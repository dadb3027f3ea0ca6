#!/usr/bin/env bash
# A Slurm job array that fills the mesh files of a list (docs/batch.md):
# task k runs the CLI's batch mode on lines [k * CHUNK, (k + 1) * CHUNK) of
# the list, writing its outputs into OUTDIR and its report into
# OUTDIR/reports/part-k.json. After the array, merge the reports:
#
#   n=$(grep -c -v -e '^[[:space:]]*$' -e '^[[:space:]]*#' files.txt)
#   job=$(sbatch --parsable --array=0-$(( (n + 50 - 1) / 50 - 1 )) \
#         --export=ALL,LIST=files.txt,OUTDIR=filled,CHUNK=50 docs/slurm_fill.sh)
#   sbatch --dependency=afterany:$job --wrap \
#     "python3 scripts/merge_reports.py --list files.txt -o filled/report.json filled/reports/part-*.json"
#
# Set FOLDFILL to the CLI's path when it is not on the nodes' PATH, and
# FILL_OPTIONS to options for every file (e.g. "--holes all --lambda 0.001").
# The list's paths and OUTDIR must be on a file system all nodes see.
#SBATCH --job-name=foldfill
#SBATCH --cpus-per-task=4
#SBATCH --mem=8G
#SBATCH --time=02:00:00
#SBATCH --output=foldfill-%A_%a.log
set -euo pipefail

: "${LIST:?set LIST, the file list}" "${OUTDIR:?set OUTDIR, the output folder}"
chunk=${CHUNK:-50}
task=${SLURM_ARRAY_TASK_ID:?run this as a job array (sbatch --array=...)}
cli=${FOLDFILL:-foldfill}
# The holes of a file are filled in parallel on the task's cores.
export OMP_NUM_THREADS=${SLURM_CPUS_PER_TASK:-1}

mapfile -t files < <(grep -v -e '^[[:space:]]*$' -e '^[[:space:]]*#' "$LIST" |
                     tail -n +$((task * chunk + 1)) | head -n "$chunk")
if ((${#files[@]} == 0)); then
  echo "task $task: no file (the list has fewer than $((task * chunk + 1)) lines)"
  exit 0
fi
mkdir -p "$OUTDIR/reports"
# Exit code 11: some file of the chunk failed; its report says which. The
# other files of the chunk are written all the same.
# shellcheck disable=SC2086  # FILL_OPTIONS is a list of options
exec "$cli" fill "${files[@]}" -o "$OUTDIR" --report "$OUTDIR/reports/part-$task.json" \
  --quiet ${FILL_OPTIONS:-}
