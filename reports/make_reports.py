#!/usr/bin/python3
"""Build cmc's reports: reports/validation/, reports/performance/, reports/challenge/.

usage: /usr/bin/python3 reports/make_reports.py [--validation DIR ...] [--results DIR]
           [--bench FILE] [--reference DIR] [--cases DIR] [--out DIR] [--only NAME ...]

  --validation DIR  folders of `cmc validate --out DIR` results (repeatable; default
                    build/validation and results/validation; the newest summary of a
                    case wins)
  --results DIR     results folder (default results/): results/performance/*.json and
                    results/challenge*/ runs
  --bench FILE      Google Benchmark JSON (default build/bench.json)
  --reference DIR   stored reference curves (default reference/)
  --cases DIR       challenge case files, for the "what to run" hints (default cases/challenge)
  --out DIR         where the reports go (default reports/)
  --only NAME       validation | performance | challenge (repeatable; default all)

Missing inputs never fail the run: each becomes a line in the report's index.md saying
what to run. Exit codes: 0 done, 2 bad arguments, 3 matplotlib/numpy missing.
Run through scripts/report.sh, which passes the repository's paths.
"""
import argparse
import os
import sys


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[1], add_help=True,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--validation", action="append")
    ap.add_argument("--results", default="results")
    ap.add_argument("--bench", default="build/bench.json")
    ap.add_argument("--reference", default="reference")
    ap.add_argument("--cases", default="cases/challenge")
    ap.add_argument("--out", default="reports")
    ap.add_argument("--only", action="append", choices=["validation", "performance", "challenge"])
    a = ap.parse_args(argv)
    try:
        import numpy  # noqa: F401
        import matplotlib  # noqa: F401
    except ImportError as e:
        print(f"make_reports.py: {e}: install python3-numpy and python3-matplotlib and run with /usr/bin/python3",
              file=sys.stderr)
        return 3
    from cmc.report import challenge as challenge_report, performance as performance_report
    from cmc.report import validation as validation_report
    from cmc.report.common import HAVE_H5PY

    only = set(a.only or ["validation", "performance", "challenge"])
    validation_dirs = a.validation or ["build/validation", "results/validation"]
    jobs = [
        ("validation", lambda out, notes: validation_report.build(validation_dirs, a.reference, out, notes)),
        ("performance", lambda out, notes: performance_report.build(os.path.join(a.results, "performance"),
                                                                    a.bench, out, notes, a.reference)),
        ("challenge", lambda out, notes: challenge_report.build(a.results, a.cases, out, notes, a.reference)),
    ]
    status = 0
    for name, job in jobs:
        if name not in only:
            continue
        out = os.path.join(a.out, name)
        os.makedirs(out, exist_ok=True)
        # The folder is generated: clear what an earlier run drew, so stale figures go.
        for sub in (out, os.path.join(out, "data")):
            if os.path.isdir(sub):
                for f in os.listdir(sub):
                    if f.endswith((".png", ".csv")) or f == "index.md":
                        os.remove(os.path.join(sub, f))
        notes = []
        if not HAVE_H5PY:
            notes.append("h5py is missing (install python3-h5py): result.h5 fields were not read")
        try:
            text = job(out, notes)
        except Exception as e:  # a report must not take the others down; say what broke
            import traceback
            traceback.print_exc()
            text = f"# {name} report\n\nThe report failed: {type(e).__name__}: {e}\n"
            status = 1
        if notes:
            text += "\n## Notes\n\n" + "\n".join(f"- {n}" for n in dict.fromkeys(notes)) + "\n"
        with open(os.path.join(out, "index.md"), "w") as f:
            f.write(text)
        print(f"report: {os.path.join(out, 'index.md')}")
    return status


if __name__ == "__main__":
    sys.exit(main())
