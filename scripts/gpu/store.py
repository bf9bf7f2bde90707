#!/usr/bin/python3
"""Store GPU runs made by scripts/gpu/check.sh as a reference with provenance (issue 16).

    /usr/bin/python3 scripts/gpu/store.py --device "NVIDIA H100 80GB HBM3" --date YYYY-MM-DD CHECK_OUT [CHECK_OUT ...]

CHECK_OUT: a folder check.sh wrote (--out): runs/<backend>-<kind>-<n>/summary.json and, beside
it, <tag>.command (the command as check.sh ran it) and <tag>.gpu-memory (nvidia-smi's
samples). Each run becomes one record of
reference/gpu/runs.json (replacing a record of the same tag): the command that made it, the
device, the date, iterations, FFT pairs, the steps' solve time, the FFT pair time measured in
the same run, the answer (a_r, repulsive a_r, mean gap) and the GPU memory peak. The
challenge and performance reports print them (reports/challenge_report.py,
reports/performance_report.py). Uses the standard library only.
"""
import argparse
import glob
import json
import os
import sys

KINDS = ("hardwall", "hardwall_plain", "adhesive", "shape")  # check.sh's stages
TABOR = "tabor_mu"  # check.sh's tabor:N:MU stage: kind tabor_mu<MU>, one point of the Tabor sweep


def dx_over_rho(s):
    f = s.get("surface_facts", {})
    rho = f.get("specified_range") or f.get("interaction_range")
    return s["grid"]["dx"] / rho if rho else None


def record(run_dir, device):
    tag = os.path.basename(run_dir)
    parts = tag.split("-")
    if len(parts) != 3 or not (parts[1] in KINDS or parts[1].startswith(TABOR)):
        return None
    backend, kind, n = parts[0], parts[1], int(parts[2])
    s = json.load(open(os.path.join(run_dir, "summary.json")))
    steps, t = s["steps"], s["timing"]
    last = steps[-1]
    obs = last.get("observables", {})
    beside = os.path.dirname(os.path.dirname(run_dir))  # check.sh's --out: <tag>.command, <tag>.gpu-memory
    try:
        command = open(os.path.join(beside, tag + ".command")).read().strip()
    except FileNotFoundError:
        sys.exit(f"store.py: {run_dir}: no {tag}.command beside it (made by a check.sh that did not record "
                 "its commands): run the stage again")
    samples = os.path.join(beside, tag + ".gpu-memory")
    peak = None
    if os.path.exists(samples):
        vals = [float(x) for x in open(samples).read().split() if x.strip().replace(".", "", 1).isdigit()]
        peak = max(vals) if vals else None
    return {
        "tag": tag, "kind": kind, "n": n, "backend": backend,
        "device": device if backend == "cuda" else "host CPU of the GPU machine",
        "host_threads": s["grid"].get("threads"),
        "command": command,
        "status": s["status"],
        "iterations": t["iterations"], "fft_pairs": t["fft_pairs"],
        "solve_s": sum(x["wall_s"] for x in steps), "run_s": t["wall_s"],
        "fft_pair_s": t["fft_pair_s"], "time_per_iteration": t["time_per_iteration"],
        "time_per_fft_pair": t["time_per_fft_pair"], "fft_share": t["fft_share"],
        "outer_steps": last.get("diagnostics", {}).get("outer_iterations"),
        # dx over the problem's ρ (a coarse-grained law's own length is larger: shape)
        "dx_over_rho": dx_over_rho(s),
        "a_r": last["contact_fraction"], "a_rep": obs.get("repulsive_fraction"), "mean_gap_m": last["mean_gap"],
        "gpu_peak_mib": peak,
        # the Tabor sweep's runs (kind tabor_mu<MU>): the mu_T the run had
        "tabor": s.get("case", {}).get("interaction", {}).get("tabor"),
        "bistability_number": s.get("surface_facts", {}).get("bistability_number"),
    }


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("outs", nargs="+", help="folders scripts/gpu/check.sh wrote (--out)")
    ap.add_argument("--device", required=True, help="the GPU, as nvidia-smi names it (check.sh's first line)")
    ap.add_argument("--date", required=True, help="the day the runs were made (YYYY-MM-DD)")
    ap.add_argument("--store", default="reference/gpu/runs.json")
    a = ap.parse_args(argv)
    data = {"what": "runs of the CUDA backend (issue 16), made with scripts/gpu/check.sh and stored by "
                    "scripts/gpu/store.py", "records": []}
    if os.path.exists(a.store):
        data = json.load(open(a.store))
    by_tag = {r["tag"]: r for r in data["records"]}
    for out in a.outs:
        for d in sorted(glob.glob(os.path.join(out, "runs", "*"))):
            if not os.path.exists(os.path.join(d, "summary.json")):
                continue
            r = record(d, a.device)
            if r is None:
                print(f"store.py: {d}: not a check.sh run (<backend>-<kind>-<n>); skipped", file=sys.stderr)
                continue
            r["date"] = a.date
            by_tag[r["tag"]] = r
    data["records"] = sorted(by_tag.values(), key=lambda r: (r["kind"], r["backend"], r["n"]))
    os.makedirs(os.path.dirname(a.store), exist_ok=True)
    tmp = a.store + ".tmp"
    with open(tmp, "w") as f:
        json.dump(data, f, indent=1, sort_keys=True)
        f.write("\n")
    os.replace(tmp, a.store)
    print(f"store.py: {len(data['records'])} records in {a.store}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
