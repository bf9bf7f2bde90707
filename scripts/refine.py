#!/usr/bin/python3
"""Grid-refinement study: run one case on several grids and estimate the
discretisation error of each observable as its change between the two finest grids.

    scripts/refine.py CASE.toml --grids 2048 4096 8192 [--out results/refine/NAME]
                      [--set section.key=value ...] [--cmc build/cmc]

Each grid runs `cmc run CASE --set grid.n=N` into OUT/n<N>/; a grid whose
summary.json already says "converged" is not run again (so an interrupted study
resumes). The table (OUT/refinement.md, OUT/refinement.json) lists every scalar
observable of the last load step per grid, the relative change between the two
finest grids (the estimated error of the finest), and the grid spacing relative to
the surface's short cutoff. For the challenge surface, only grids of at least 2048
points hold the whole spectrum; coarser grids solve a low-passed surface and are
flagged in the table.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile


def run(cmc, case, n, out, overrides):
    summary = os.path.join(out, "summary.json")
    if os.path.exists(summary):
        with open(summary) as f:
            s = json.load(f)
        if s.get("status") == "converged" and s["grid"]["nx"] == n:
            print(f"refine: n = {n}: reusing {summary}", file=sys.stderr)
            return s
    cmd = [cmc, "run", case, "--out", out, "--set", f"grid.n={n}", "--set", "output.fields=false"]
    for o in overrides:
        cmd += ["--set", o]
    print("refine: " + " ".join(cmd), file=sys.stderr)
    r = subprocess.run(cmd)
    if r.returncode not in (0, 3):
        sys.exit(f"refine: cmc failed on n = {n} (exit {r.returncode})")
    with open(summary) as f:
        return json.load(f)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case")
    ap.add_argument("--grids", type=int, nargs="+", required=True)
    ap.add_argument("--out")
    ap.add_argument("--set", action="append", default=[], dest="overrides")
    ap.add_argument("--cmc", default=os.path.join(os.path.dirname(__file__), "..", "build", "cmc"))
    a = ap.parse_args()
    if len(a.grids) < 2 or sorted(a.grids) != a.grids:
        sys.exit("refine: --grids needs at least two increasing grid sizes")
    name = os.path.splitext(os.path.basename(a.case))[0]
    out = a.out or os.path.join("results", "refine", name)
    os.makedirs(out, exist_ok=True)

    runs = {n: run(a.cmc, a.case, n, os.path.join(out, f"n{n}"), a.overrides) for n in a.grids}
    keys = []
    for s in runs.values():
        for k in s["steps"][-1].get("observables", {}):
            if k not in keys:
                keys.append(k)
    for k in ["penetration", "mean_gap", "contact_fraction", "iterations", "wall_s"]:
        if k not in keys:
            keys.append(k)

    def value(s, k):
        st = s["steps"][-1]
        return st.get("observables", {}).get(k, st.get(k))

    fine, finer = a.grids[-2], a.grids[-1]
    rows = []
    for k in keys:
        vals = [value(runs[n], k) for n in a.grids]
        v1, v2 = value(runs[fine], k), value(runs[finer], k)
        change = abs(v2 - v1) / abs(v2) if (v1 is not None and v2 not in (None, 0)) else None
        rows.append({"observable": k, "values": vals, "relative_change_finest": change})

    facts = {n: runs[n].get("surface_facts", {}) for n in a.grids}
    lines = [f"# Refinement study: {a.case}", "",
             "Estimated discretisation error of each observable = its relative change between the two finest grids "
             f"({fine}² → {finer}²). Last load step; SI units.", "",
             "| observable | " + " | ".join(f"n = {n}" for n in a.grids) + " | change |",
             "|---|" + "---|" * (len(a.grids) + 1)]
    for r in rows:
        vals = " | ".join("—" if v is None else f"{v:.6g}" for v in r["values"])
        ch = "—" if r["relative_change_finest"] is None else f"{r['relative_change_finest']:.2e}"
        lines.append(f"| {r['observable']} | {vals} | {ch} |")
    lines += ["", "| grid | dx (m) | dx / λ_s | status | modes dropped |", "|---|---|---|---|---|"]
    for n in a.grids:
        s = runs[n]
        f = facts[n]
        lines.append(f"| {n}² | {s['grid']['dx']:.4g} | {f.get('dx_over_cutoff_wavelength', float('nan')):.3g} | "
                     f"{s['status']} | {int(f.get('modes_dropped', 0))} |")
    text = "\n".join(lines) + "\n"
    for fname, content in [("refinement.md", text),
                           ("refinement.json", json.dumps({"case": a.case, "grids": a.grids, "rows": rows}, indent=1))]:
        fd, tmp = tempfile.mkstemp(dir=out)
        with os.fdopen(fd, "w") as f:
            f.write(content)
        os.replace(tmp, os.path.join(out, fname))
    print(text)


if __name__ == "__main__":
    main()
