"""The reports (scripts/report.sh, reports/make_reports.py): reading runs, stores and references,
and drawing with matplotlib (Agg). One module a report: validation, performance, challenge (its
runs, sweeps and figures in challenge_*), with best, speed and surface for the challenge's
sections, and common for the helpers they share."""
