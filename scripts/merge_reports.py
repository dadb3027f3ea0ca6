#!/usr/bin/env python3
"""Merges JSON reports of `foldfill fill` into one batch report.

    merge_reports.py [-o MERGED.json] [--list LIST] REPORT.json...

Each input is a batch report ({"files": [...], "totals": ..., "seconds_total"})
or the report of one file (`fill IN -o OUT --report R`), taken as one entry of
"files" with a status derived from its holes. The output has the batch
report's form: "files" sorted by input path, "totals" (filled, unchanged,
failed; a partly filled file counts as failed, as in the CLI), and
"seconds_total", the sum of the runs' wall times (not the elapsed time when
they ran in parallel), plus "reports", the count of reports merged. With
--list (one mesh path a line), a listed file that no report names (its run
failed before writing a report: a file that cannot be read, a crash) gets an
entry of status "failed".
Standard library only; prints the merged report when -o is not given.
"""

import argparse
import json
import os
import sys


def file_entries(report, path):
    """The "files" entries of one report."""
    if "files" in report:
        return report["files"]
    if "holes" in report:
        holes = report["holes"]
        filled = sum(1 for hole in holes if hole.get("filled"))
        if not holes:
            status = "unchanged"
        elif filled == len(holes):
            status = "filled"
        else:
            status = "partly_filled" if filled else "failed"
        return [dict(report, status=status)]
    raise ValueError("{}: neither a batch report nor a file's report".format(path))


def merge(reports, listed=()):
    """The merged report of (path, report) pairs, with an entry for each of
    the `listed` inputs that none of them names."""
    files, seconds = [], 0.0
    for path, report in reports:
        files.extend(file_entries(report, path))
        seconds += report.get("seconds_total", 0.0)
    named = {entry.get("input") for entry in files}
    for path in listed:
        if path not in named:
            files.append({"input": path, "output": None, "status": "failed",
                          "reason": "no report: the run of this file failed (see its error)"})
            named.add(path)
    files.sort(key=lambda entry: str(entry.get("input", "")))
    totals = {"filled": 0, "unchanged": 0, "failed": 0}
    for entry in files:
        status = entry.get("status", "failed")
        totals["filled" if status == "filled" else
               "unchanged" if status == "unchanged" else "failed"] += 1
    return {"files": files, "totals": totals, "seconds_total": seconds, "reports": len(reports)}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("reports", nargs="*", help="reports to merge (missing ones are skipped)")
    parser.add_argument("-o", "--output", help="write the merged report here")
    parser.add_argument("--list", help="the file list of the batch (one path a line)")
    args = parser.parse_args(argv)
    listed = []
    if args.list:
        with open(args.list) as f:
            listed = [line.strip() for line in f
                      if line.strip() and not line.lstrip().startswith("#")]
    reports = []
    for path in args.reports:
        if not os.path.exists(path):
            continue  # a run that stopped before writing its report
        with open(path) as f:
            try:
                reports.append((path, json.load(f)))
            except json.JSONDecodeError as e:
                sys.exit("merge_reports.py: {}: not JSON ({})".format(path, e))
    try:
        merged = merge(reports, listed)
    except ValueError as e:
        sys.exit("merge_reports.py: {}".format(e))
    text = json.dumps(merged, indent=1) + "\n"
    if args.output:
        tmp = args.output + ".tmp"
        with open(tmp, "w") as f:
            f.write(text)
        os.replace(tmp, args.output)
    else:
        sys.stdout.write(text)


if __name__ == "__main__":
    main()
