"""Shared helpers of the cmc reports (reports/make_reports.py).

Only the Python standard library, numpy, matplotlib and h5py (Debian's python3-*
packages, run with /usr/bin/python3). Every reader returns None (and says why) instead
of raising on a missing or malformed input: a report never crashes on missing data.
"""
import glob
import json
import math
import os

import numpy as np

try:
    import h5py  # noqa: F401
    HAVE_H5PY = True
except ImportError:  # pragma: no cover - depends on the machine
    HAVE_H5PY = False

import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "python"))
from cmc.analysis.family import (FAMILY_QUANTITIES, FAMILY_STORE, condition_members, family_members,  # noqa: E402,F401
                                 measured_members, seed_members, strategy_errors, strategy_run_near)
from cmc.analysis.refinement import (MIN_ORDER, REFINEMENT_BISTABILITY, own_refinement,  # noqa: E402,F401
                                     own_refinement_words)

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# The challenge's parameters (problem definition, "Summary of default parameters").
CHALLENGE = {
    "Estar": 25e6,          # Pa, E* (rms gradient g = 1, so E* g = 25 MPa)
    "L": 1e-4,              # m, system size
    "lambda_r": 20e-6,      # m, roll-off wavelength
    "lambda_s": 0.1e-6,     # m, short-wavelength cutoff
    "rho": 2.071e-9,        # m, range of the exponential adhesion
    "gamma0": 50e-3,        # J/m^2
    "p0": 250e3,            # Pa, reference pressure
    "tabor": 3.0,
}


def load_json(path, notes=None):
    """The parsed JSON file, or None (with a note) when it is missing or malformed."""
    try:
        with open(path) as f:
            return json.load(f)
    except FileNotFoundError:
        return None
    except (OSError, ValueError) as e:
        if notes is not None:
            notes.append(f"`{path}` could not be read ({e}); skipped")
        return None


def get(d, *keys, default=None):
    """d[k0][k1]... or default if any level is missing or not a dict."""
    for k in keys:
        if not isinstance(d, dict) or k not in d:
            return default
        d = d[k]
    return d


def case_name(summary):
    """The run's case name: summary["case"]["case"]["name"] (the resolved case file) or
    summary["case"]["name"]."""
    c = summary.get("case")
    if isinstance(c, dict):
        n = get(c, "case", "name")
        if isinstance(n, str):
            return n
        if isinstance(c.get("name"), str):
            return c["name"]
    if isinstance(c, str):
        return c
    return None


def finite(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


def md_table(header, rows):
    """A Markdown table."""
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for r in rows:
        out.append("| " + " | ".join(str(c).replace("|", "\\|").replace("\n", " ") for c in r) + " |")
    return "\n".join(out)


def fmt(x, digits=4):
    if x is None:
        return "–"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    if isinstance(x, (float, np.floating)):
        if not math.isfinite(x):
            return str(x)
        if x == 0:
            return "0"
        if 1e-3 <= abs(x) < 1e5:
            return f"{x:.{digits}g}"
        return f"{x:.{digits - 1}e}"
    return str(x)


def savefig(fig, path):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def read_reference_csv(path):
    """A cmc reference CSV (reference/README.md): (metadata dict, column names, 2-D
    array with one column per name), or None if missing/malformed."""
    try:
        meta, names, rows = {}, None, []
        with open(path) as f:
            for line in f:
                s = line.strip()
                if not s:
                    continue
                if s.startswith("#"):
                    body = s[1:].strip()
                    if names is None and ":" in body:
                        k, v = body.split(":", 1)
                        meta[k.strip()] = v.strip()
                    continue
                if names is None:
                    names = [c.strip() for c in s.split(",")]
                    continue
                rows.append([float(v) for v in s.split(",")])
        if names is None or not rows:
            return None
        return meta, names, np.array(rows)
    except (OSError, ValueError):
        return None


def write_csv(path, columns, header_comment=None):
    """Write columns [(name, values), ...] as CSV in the format `cmc check` reads."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    n = min(len(v) for _, v in columns)
    with open(path, "w") as f:
        if header_comment:
            for line in header_comment.splitlines():
                f.write(f"# {line}\n")
        f.write(",".join(name for name, _ in columns) + "\n")
        for i in range(n):
            f.write(",".join(f"{float(v[i]):.9e}" for _, v in columns) + "\n")


def find_summaries(patterns):
    """Paths of summary.json files matching any of the glob patterns (recursive), sorted."""
    out = set()
    for p in patterns:
        for f in glob.glob(p, recursive=True):
            if os.path.basename(f) == "summary.json" and os.path.isfile(f):
                out.add(os.path.normpath(f))
    return sorted(out)


def h5_open(path, notes=None):
    if not HAVE_H5PY:
        if notes is not None:
            notes.append("h5py is missing (install python3-h5py): fields in result.h5 were not read")
        return None
    if not os.path.isfile(path):
        return None
    try:
        import h5py
        return h5py.File(path, "r")
    except OSError as e:
        if notes is not None:
            notes.append(f"`{path}` could not be opened ({e}); skipped")
        return None


def step_groups(h5):
    """Names of the step groups of a result.h5 in order (step_0000, ...)."""
    return sorted(k for k in h5.keys() if k.startswith("step_"))


def rel(path, start):
    try:
        return os.path.relpath(path, start)
    except ValueError:
        return path


# ---------------------------------------------------------------- round-off spread
# Measured by scripts/roundoff_spread.py from pairs of runs of one case by two builds or at
# two thread counts.
ROUNDOFF_STORE = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "reference", "challenge",
                              "roundoff_spread.json")


def roundoff_note(path=ROUNDOFF_STORE, rel=None):
    """One sentence on round-off for error statements: a rerun of one build at one thread count
    gives the same bits; between builds and thread counts the measured spread (largest relative
    difference per quantity), or that it was not measured."""
    head = ("A rerun of one build at one thread count gives the same bits; another build (each plans its "
            "FFTs at build time) or thread count rounds differently")
    doc = load_json(path)
    big = (doc or {}).get("largest") or {}
    parts = [f"{v['relative']:.2g} in {v.get('label', k)}" for k, v in big.items()
             if isinstance(v, dict) and isinstance(v.get("relative"), (int, float))]
    if not parts:
        return head + ", a spread not measured here."
    where = rel(path) if rel else "reference/challenge/roundoff_spread.json"
    n = len(doc.get("comparisons") or [])
    return (head + f": the spread that causes, measured on {n} pair{'s' if n != 1 else ''} of runs (`{where}`), "
            "is at most " + ", ".join(parts) + " (relative), and is not added to the bands.")


# ---------------------------------------------------------------- the scaled challenge family
# Its store (scripts/scaled_family.py --store) and the coarse-grid strategy's measured error,
# shared by scripts/scaled_family.py, scripts/challenge_reference.py and the challenge report.


# The coarse-grainings of the exponential law (cases/README.md, [interaction] coarse_graining),
# each a resolution strategy whose error the family measures; "plain" is the law at grid points.
STRATEGIES = ("range", "shape")
STRATEGY_WORDS = {"plain": "the plain (unmodified) interaction", "range": "the range coarse-graining",
                  "shape": "the shape coarse-graining"}


def run_strategy(summary):
    """The strategy of a run (its summary.json): its interaction.coarse_graining, or "plain"."""
    cg = get(summary, "case", "interaction", "coarse_graining")
    return cg if cg in STRATEGIES else "plain"


def run_strategy_error(summary, short, members=None):
    """For an adhesive run with exponential adhesion (its summary.json): its dx over the case's
    range rho, and the relative error for `short` (a_r, a_rep, mean_gap) that its strategy
    (interaction.coarse_graining "range" or "shape", else "plain") has on the family at that dx/rho,
    with what it was measured on; (dx/rho, None, []) where the family has no run near; None for
    other runs."""
    inter = get(summary, "case", "interaction", default={}) or {}
    if inter.get("kind") != "exponential":
        return None
    strategy = run_strategy(summary)
    facts = summary.get("surface_facts") or {}
    rho = facts.get("specified_range") or facts.get("interaction_range")
    g = summary.get("grid") or {}
    dx = g.get("dx_m") or g.get("dx")
    if not (finite(rho) and rho > 0 and finite(dx) and dx > 0):
        return None
    k = dx / rho
    err, used = strategy_errors(measured_members() if members is None else members, strategy, k)
    return k, (err or {}).get(short), used


def transfer_check(members=None, strategy="range"):
    """Whether the family's members behave like the challenge (s = 1) on coarse grids: for each
    s = 1 grid with both a plain run and one of the strategy, the ratio strategy/plain of a_r
    there and in each member s > 1 at the same dx/rho (within a factor 1.3). The ratio needs no
    converged answer, so a member whose resolved run is still missing takes part too. Returns
    [(n, dx/rho, ratio at s = 1, s, ratio in the family)]; [] when the store lacks the runs. The
    strategy errors transfer to s = 1 only if the ratios agree."""
    members = family_members() if members is None else members
    out = []
    for m1 in members:
        if m1["s"] != 1:
            continue
        runs1 = {r["role"]: r for r in m1["runs"]}
        for role, p1 in runs1.items():
            if not role.startswith("plain_") or strategy + "_" + role[6:] not in runs1:
                continue
            r1 = runs1[strategy + "_" + role[6:]]
            k = p1["dx_over_rho"]
            for m in members:
                if m["s"] == 1:
                    continue
                near = [r for r in m["runs"] if r["role"].endswith("rho") and r["role"].split("_")[0] in ("plain", strategy)
                        and abs(math.log(r["dx_over_rho"] / k)) < math.log(1.3)]
                by = {r["role"].split("_")[0]: r for r in near}
                if "plain" in by and strategy in by:
                    out.append((p1["n"], k, r1["a_r"] / p1["a_r"], m["s"], by[strategy]["a_r"] / by["plain"]["a_r"]))
    return out


def s_extrapolation(members=None):
    """The second route to the challenge (s = 1): per quantity (a_r, a_rep, mean_gap), the ratio
    R(s) = adhesive reference / adhesionless value of each member with both, extrapolated to s = 1
    and multiplied by the challenge's own adhesionless value (its hard wall converges on grids a
    machine holds). Why the ratio: along the family w/(E* lambda_s), rho/lambda_s, mu_T, the rms
    slope and p/(E* rms slope) stay fixed and only the bandwidth lambda_r/lambda_s = 200/s
    changes, which moves the adhesionless values themselves a lot (the mean gap follows the rms
    height, 3.06 um at s = 32 against 1.01 um at s = 1); the ratio carries what adhesion adds.

    Two models of the curve, each a straight line through the two members nearest s = 1: one in
    log s (the bandwidth's octaves), one in s. Two points cannot tell them apart; a third member
    can test them. The held-out check predicts the nearest member's R from the next two, with
    both lines: where the two predictions bracket the measured R (within its error) for a
    quantity, the lines are taken to bracket the curve at s = 1 too (an assumption one octave of
    evidence supports, not a bound), and the value is their midpoint with half their distance as
    the model error. Without a third member, or where the check does not bracket, the value is
    the midpoint and the model error the whole distance between the lines (either could be
    wrong by that much). Error = model error + the members' refinement errors carried through
    the lines' weights (the larger of the two lines') + the adhesionless value's refinement
    error. Returns {"members": [s, ...], short: {...}} or None without two members and the
    challenge's adhesionless value."""
    members = family_members() if members is None else members
    by_s = {m["s"]: m for m in members}
    ch = by_s.get(1, {}).get("adhesionless") or {}
    fam = sorted(s for s, m in by_s.items() if s > 1 and m.get("reference", {}).get("a_r") and m.get("adhesionless"))
    if len(fam) < 2 or not ch.get("a_r"):
        return None
    sa, sb = fam[0], fam[1]  # nearest s = 1 first
    sc = fam[2] if len(fam) > 2 else None
    out = {"members": [sa, sb] + ([sc] if sc else [])}

    def line(pa, pb, x1, log):
        """A line through (s_a, R_a), (s_b, R_b) (each (s, (R, error))) at s = x1, in log s or in s:
        its value and the members' errors carried through its weights."""
        (xa, (Ra, ea)), (xb, (Rb, eb)) = pa, pb
        f = math.log if log else float
        t = (f(x1) - f(xa)) / (f(xb) - f(xa))
        return Ra + t * (Rb - Ra), abs(1 - t) * ea + abs(t) * eb

    for _, short, unit in FAMILY_QUANTITIES:
        ratios = {}
        for s in out["members"]:
            ref, hw = by_s[s]["reference"][short], by_s[s]["adhesionless"][short]
            R = ref["value"] / hw["value"]
            ratios[s] = (R, R * (ref["refinement_error"] / abs(ref["value"]) + hw["refinement_error"] / abs(hw["value"])))
        pa, pb = (sa, ratios[sa]), (sb, ratios[sb])
        R_log, e_log = line(pa, pb, 1, True)
        R_lin, e_lin = line(pa, pb, 1, False)
        held_out = None
        if sc:
            pc = (sc, ratios[sc])
            p_log, pe_log = line(pb, pc, sa, True)
            p_lin, pe_lin = line(pb, pc, sa, False)
            Ra, ea = ratios[sa]
            lo, hi = min(p_log, p_lin), max(p_log, p_lin)
            held_out = {"member": sa, "from": [sb, sc], "measured": Ra, "measured_error": ea,
                        "log_s": p_log, "linear_s": p_lin,
                        "bracketed": lo - max(pe_log, pe_lin) - ea <= Ra <= hi + max(pe_log, pe_lin) + ea}
        half = bool(held_out and held_out["bracketed"])
        R_mid = 0.5 * (R_log + R_lin)
        model = abs(R_log - R_lin) * (0.5 if half else 1.0)
        hw1 = ch[short]
        value = R_mid * hw1["value"]
        err = (model + max(e_log, e_lin)) * abs(hw1["value"]) + abs(R_mid) * hw1["refinement_error"]
        out[short] = {"value": value, "error": err, "unit": unit, "ratio_at_1": R_mid, "ratio_at_1_log_s": R_log,
                      "ratio_at_1_linear_s": R_lin, "ratio_error_propagated": max(e_log, e_lin), "ratio_error_model": model,
                      "held_out": held_out,
                      "ratios": {str(s): {"value": r, "error": e} for s, (r, e) in ratios.items()},
                      "adhesionless_at_1": hw1}
    return out


def s_extrapolation_verdict(x):
    """Sentences on how far the second route (s_extrapolation's result x) can be used: the held-out
    check, if there is one, and the quantities whose error is more than half their value."""
    sa, sb = x["members"][0], x["members"][1]
    text = ""
    checks = [(short, x[short]["held_out"]) for _, short, _ in FAMILY_QUANTITIES if x[short].get("held_out")]
    if checks:
        h0 = checks[0][1]
        parts = [f"{short} {h['measured']:.4f} measured, {h['log_s']:.4f} (log s) and {h['linear_s']:.4f} (s) predicted"
                 for short, h in checks]
        inside = [short for short, h in checks if h["bracketed"]]
        outside = [short for short, h in checks if not h["bracketed"]]
        text += (f"Held-out check: R at s = {h0['member']} predicted from s = {h0['from'][0]} and {h0['from'][1]}: "
                 + "; ".join(parts) + ". ")
        if inside:
            miss = min(abs(h[m] - h["measured"]) / h["measured_error"] for short, h in checks if h["bracketed"]
                       for m in ("log_s", "linear_s") if h["measured_error"] > 0)
            text += ("The two lines bracket the measured ratio for " + ", ".join(inside) + f", each line off by at "
                     f"least {miss:.3g} times the measured ratio's error one octave out: so at s = 1, "
                     f"{math.log2(sa):.3g} octaves further, the value is their midpoint and half their distance its "
                     "model error (assumed to bracket there too; not a bound). ")
        if outside:
            text += ("They do not bracket it for " + ", ".join(outside) + ": the whole distance between the lines is "
                     "its model error. ")
    loose = [short for _, short, _ in FAMILY_QUANTITIES if x[short]["error"] > 0.5 * abs(x[short]["value"])]
    if loose:
        text += (f"With the members s = {sb} and {sa} this route is not informative for " + ", ".join(loose) + ": the "
                 "error is more than half the value, mostly the distance between the two lines.")
    elif not checks:
        text += "A third member would test the two lines (the held-out check)."
    return text.strip()


def transfer_caveat(members=None, strategy="range"):
    """One sentence on transfer_check for error statements, or "" when it cannot be made: per s = 1
    grid the ratio there and in each member (largest s first), and whether the members approach
    the challenge's ratio as s falls toward 1."""
    rows = transfer_check(members, strategy)
    if not rows:
        return ""
    by_grid = {}
    for n, k, a, s, b in rows:
        by_grid.setdefault((n, k, a), []).append((s, b))
    parts, approach = [], True
    for (n, k, a), fam in sorted(by_grid.items(), key=lambda x: -x[0][0]):
        fam.sort(reverse=True)
        parts.append(f"{n}^2 (dx = {k:.3g} rho): " + ", ".join(f"{b:.3f} at s = {s}" for s, b in fam) + f", {a:.3f} at s = 1")
        dist = [abs(math.log(b / a)) for _, b in fam]
        approach = approach and len(dist) > 1 and all(d1 < d0 for d0, d1 in zip(dist, dist[1:]))
    agree = all(abs(math.log(a / b)) < math.log(1.05) for _, _, a, _, b in rows)
    text = f"Transfer check, a_r of the {strategy} run over the plain run at the same dx/rho: {'; '.join(parts)}. "
    if agree:
        return text + "They agree within 5 %, as the transfer assumes."
    nearest = min(s for _, _, _, s, _ in rows)
    with_ref = {m["s"] for m in (family_members() if members is None else members) if m.get("reference", {}).get("a_r")}
    nearer = ("a member nearer s = 1 (s = 8, resolved on 8192²)" if nearest not in with_ref or nearest > 8 else
              f"a member nearer s = 1 than s = {nearest}")
    if nearest not in with_ref:
        nearer = f"s = {nearest}'s resolved run (its ratio is measured, its errors are not yet)"
    if approach:
        return text + ("They do not agree, but they approach the challenge's as s falls toward 1, so the band (the "
                       "largest error over the members with a reference, hence that of the member farthest from "
                       f"s = 1) is indicative and probably pessimistic, not a bound; {nearer} would test the trend.")
    return text + ("They do not agree, so the family does not reproduce the challenge's coarse-grid behaviour and the "
                   f"band is indicative, not a bound; {nearer} is needed.")


# Issue 13's targets for a strategy at dx = 2 rho and 4 rho: relative error of a_r and of the mean gap.
STRATEGY_TARGETS = {2: (0.03, 0.005), 4: (0.06, 0.01)}


def _same(a, b):
    return (a is None and b is None) or (a is not None and b is not None and abs(a / b - 1) < 0.01)


def own_tabor(summary):
    """The run's mu_T where it is not the challenge's 3 (within 1 %), else None: the condition whose
    store (condition_error's tabor) measures its band."""
    tabor = get(summary, "case", "interaction", "tabor")
    return tabor if finite(tabor) and not _same(tabor, 3.0) else None


def condition_error(strategy, dx_over_rho, tabor=None, pressure=None, members=None):
    """The strategy's error (strategy_errors) measured on the family at this condition (mu_T within
    1 %, load within 1 %; None for the challenge's own 3 and 250 kPa), or (None, []) where no
    condition store holds it or no run is near this dx/rho."""
    ms = [m for m in (condition_members() if members is None else members)
          if _same(m.get("tabor"), tabor) and _same(m.get("pressure_Pa"), pressure)]
    return strategy_errors(ms, strategy, dx_over_rho) if ms else (None, [])


def run_band(summary, short):
    """The error band (relative) of an adhesive run for `short`: the larger of its strategy's error
    measured on the family at mu_T = 3 and 250 kPa (run_strategy_error) and, where the family was
    also run at the run's own mu_T (condition_members), the error measured there. Returns (dx/rho,
    band, error at mu_T = 3, error at the run's mu_T, what the first was measured on), or None for
    runs without exponential adhesion; band None where neither is measured."""
    got = run_strategy_error(summary, short)
    if got is None:
        return None
    k, rel, used = got
    tabor, at = own_tabor(summary), None
    if tabor is not None:
        err, _ = condition_error(run_strategy(summary), k, tabor=tabor)
        at = None if err is None else err[short]
    both = [x for x in (rel, at) if x is not None]
    return k, (max(both) if both else None), rel, at, used


def load_bands(summary, short, pressures):
    """Per load of an adhesive load sweep (its summary.json; pressures in Pa): the relative band for
    `short`, and a sentence on what it rests on. The band measured at mu_T = 3 and 250 kPa
    (run_band) holds at every load unless the family was also run at other loads
    (condition_members with a "pressure_Pa", scripts/scaled_family.py --pressure): then, at each
    load, the larger of it and the errors measured at the loads, interpolated linearly in log p
    between the measured loads (250 kPa's the first band) and held beyond them. None where
    nothing is measured at this dx/rho."""
    got = run_band(summary, short)
    if got is None or got[1] is None:
        return None, ""
    k, band, _, _, _ = got
    members = condition_members()
    at = [(250e3, band)]
    for p in sorted({m["pressure_Pa"] for m in members if "pressure_Pa" in m and not _same(m["pressure_Pa"], 250e3)}):
        err, _ = condition_error(run_strategy(summary), k, tabor=own_tabor(summary), pressure=p, members=members)
        if err is not None:
            at.append((p, err[short]))
    at.sort()
    if len(at) == 1:
        return [band] * len(pressures), ""
    lp = np.log([a[0] for a in at])
    rel = np.interp(np.log(np.asarray(pressures, dtype=float)), lp, [a[1] for a in at])
    words = (f"the larger of the band at 250 kPa ({100 * band:.3g} %) and the error measured on the family's s = 32 "
             "member at the sweep's other loads (" + ", ".join(f"{p / 1e3:g} kPa: {100 * e:.3g} %" for p, e in at
                                                               if not _same(p, 250e3))
             + "; reference/challenge-scaled/conditions/p*/), interpolated in log p between the measured loads and "
             "held beyond them")
    return [max(band, float(r)) for r in rel], words


def condition_checks(members=None, reference=None):
    """One row per coarse run of each condition member (plain and strategies): its signed relative
    deviation from that member's reference per quantity, and the band the challenge's references
    take at that dx/rho from the family at mu_T = 3 and 250 kPa (strategy_errors over
    measured_members()): whether the band, assumed at this condition, holds there."""
    rows = []
    base = measured_members() if reference is None else reference
    for m in (condition_members() if members is None else members):
        ref = m["reference"]
        for r in sorted(m["runs"], key=lambda r: (-r["dx_over_rho"], r["role"])):
            strategy = r["role"].split("_")[0]
            if strategy not in ("plain",) + STRATEGIES or not r["role"].endswith("rho"):
                continue
            band, _ = strategy_errors(base, strategy, r["dx_over_rho"])
            row = {"tabor": m.get("tabor", 3.0), "pressure_Pa": m.get("pressure_Pa", 250e3), "s": m["s"],
                   "strategy": strategy, "n": r["n"], "dx_over_rho": r["dx_over_rho"]}
            for _, short, _ in FAMILY_QUANTITIES:
                q = ref[short]
                dev = r[short] / q["value"] - 1
                row[short] = {"deviation": dev, "refinement": q["refinement_error"] / abs(q["value"]),
                              "band": None if band is None else band[short]}
            rows.append(row)
    return rows


def _quantity_holds(q):
    """One quantity of a condition_checks row: |deviation| plus the reference's refinement error
    within the band; None without a band."""
    return None if q["band"] is None else abs(q["deviation"]) + q["refinement"] <= q["band"]


def condition_holds(row):
    """Whether the band at mu_T = 3 and 250 kPa holds a condition_checks row (a_r and the mean gap);
    None without a band."""
    out = [h for h in (_quantity_holds(row[short]) for short in ("a_r", "mean_gap")) if h is not None]
    return None if not out else all(out)


def condition_summary(rows, strategies=("plain",)):
    """One sentence on the condition check of the given strategies' runs, or "" without rows."""
    rows = [r for r in rows if r["strategy"] in strategies and condition_holds(r) is not None]
    if not rows:
        return ""
    bad = [r for r in rows if not condition_holds(r)]
    conds = sorted({(r["tabor"], r["pressure_Pa"]) for r in rows})
    words = ", ".join(f"μ_T = {t:g} at {p / 1e3:g} kPa" for t, p in conds)
    if not bad:
        return (f"At the other conditions measured ({words}) the band measured at μ_T = 3 and 250 kPa held every "
                f"{'/'.join(strategies)} run ({len(rows)}).")
    def excess(r, short):  # (|deviation| + refinement error) / band
        q = r[short]
        return -1.0 if not q["band"] else (abs(q["deviation"]) + q["refinement"]) / q["band"]
    worst, short = max(((r, k) for r in bad for k in ("a_r", "mean_gap")), key=lambda x: excess(*x))
    q = worst[short]
    return (f"At the other conditions measured ({words}) the band measured at μ_T = 3 and 250 kPa failed "
            f"{len(bad)} of {len(rows)} {'/'.join(strategies)} runs; the worst, μ_T = {worst['tabor']:g} at "
            f"{worst['pressure_Pa'] / 1e3:g} kPa on dx = {worst['dx_over_rho']:.2f} ρ: "
            f"{'a_r' if short == 'a_r' else 'mean gap'} {100 * q['deviation']:+.{1 if short == 'a_r' else 2}f} % "
            f"against a band of ±{100 * q['band']:.{1 if short == 'a_r' else 2}f} %.")


def condition_check_lines(rows, strategies=("plain",)):
    """Markdown lines: the condition check's table (condition_checks rows of the given strategies)."""
    rows = [r for r in rows if r["strategy"] in strategies]
    if not rows:
        return []
    L = ["| μ_T | load (kPa) | run | dx/ρ | a_r: measured (ref. error) / band | mean gap: measured / band | band holds |",
         "|---|---|---|---|---|---|---|"]
    for r in rows:
        cells, holds = [], []
        for short in ("a_r", "mean_gap"):
            q = r[short]
            band = q["band"]
            cells.append(f"{100 * q['deviation']:+.1f} % ({100 * q['refinement']:.1f} %) / "
                         + ("—" if band is None else f"±{100 * band:.1f} %") if short == "a_r" else
                         f"{100 * q['deviation']:+.2f} % / " + ("—" if band is None else f"±{100 * band:.2f} %"))
            holds.append(_quantity_holds(q))
        verdict = ("no band" if all(h is None for h in holds) else
                   "yes" if all(h in (True, None) for h in holds) else
                   "**no** (" + ", ".join(k for k, h in zip(("a_r", "mean gap"), holds) if h is False) + ")")
        L.append(f"| {r['tabor']:g} | {r['pressure_Pa'] / 1e3:g} | {r['strategy']}, s = {r['s']} on {r['n']}² | "
                 f"{r['dx_over_rho']:.2f} | {cells[0]} | {cells[1]} | {verdict} |")
    return L + [""]


def realization_members(reference_dir, case_seed):
    """The family's members on every stored realization of the surface: the main store's (the case
    file's seed, `case_seed`) and those of reference/challenge-scaled/seeds/*/ (scripts/scaled_family.py
    --seed N), as {s: [(seed, member), ...]} for the members with a reference, seeds in order."""
    by_s = {}
    for m in family_members(os.path.join(reference_dir, "challenge-scaled", "scaled_family.json")):
        if m.get("reference", {}).get("a_r") and m["s"] > 1:
            by_s.setdefault(m["s"], []).append((m.get("seed", case_seed), m))
    for m in seed_members(os.path.join(reference_dir, "challenge-scaled")):
        by_s.setdefault(m["s"], []).append((m["seed"], m))
    for s in by_s:
        by_s[s].sort(key=lambda x: (x[0] is None, x[0] or 0))
    return by_s


def realization_rows(members, spacings=(2, 4)):
    """One row per realization (seed, member): the reference a_r and mean gap (± refinement error) and,
    for each spacing k and each of plain and the strategies, the deviation of that run's a_r and mean
    gap from the member's reference, marked met/not met against STRATEGY_TARGETS for the strategies.
    Then a summary row: per column the largest |deviation| and, for the strategies, how many
    realizations meet the target. Returns (header, rows)."""
    kinds = ("plain",) + STRATEGIES
    header = ["seed", "ρ (nm)", "reference a_r", "reference mean gap (µm)"] + [
        f"{kind}, {k} ρ" for k in spacings for kind in kinds]
    rows, worst, met, seen = [], {}, {}, {}
    for seed, m in members:
        ref = m["reference"]
        row = [seed if seed is not None else "?", fmt(m["rho_m"] * 1e9, 4),
               f"{ref['a_r']['value']:.4g} ± {ref['a_r']['refinement_error']:.2g}",
               f"{ref['mean_gap']['value'] * 1e6:.4g} ± {ref['mean_gap']['refinement_error'] * 1e6:.2g}"]
        runs = {r["role"]: r for r in m["runs"]}
        for k in spacings:
            for kind in kinds:
                r = runs.get(f"{kind}_{k}rho")
                col = (kind, k)
                if not r:
                    row.append("–")
                    continue
                da = r["a_r"] / ref["a_r"]["value"] - 1
                dg = r["mean_gap"] / ref["mean_gap"]["value"] - 1
                w = worst.setdefault(col, [0.0, 0.0])
                w[0], w[1] = max(w[0], abs(da)), max(w[1], abs(dg))
                cell = f"{100 * da:+.1f} % / {100 * dg:+.2f} %"
                if kind != "plain" and k in STRATEGY_TARGETS:
                    ta, tg = STRATEGY_TARGETS[k]
                    ok = abs(da) <= ta and abs(dg) <= tg
                    met[col] = met.get(col, 0) + int(ok)
                    seen[col] = seen.get(col, 0) + 1
                    cell += " (met)" if ok else " (not met)"
                row.append(cell)
        rows.append(row)
    summary = ["largest", "", "", ""]
    for k in spacings:
        for kind in kinds:
            col = (kind, k)
            if col not in worst:
                summary.append("–")
                continue
            text = f"{100 * worst[col][0]:.1f} % / {100 * worst[col][1]:.2f} %"
            if col in seen:
                text += f"; target met on {met[col]} of {seen[col]}"
            summary.append(text)
    rows.append(summary)
    return header, rows


def gpu_runs(reference_dir, notes=None):
    """The CUDA backend's runs in the run store (reference/challenge/runs.json, scripts/gpu/store.py),
    sorted by case and grid; [] when the store is missing."""
    d = load_json(os.path.join(reference_dir, "challenge", "runs.json"), notes)
    recs = d.get("records", []) if isinstance(d, dict) else []
    return sorted((r for r in recs if r.get("backend") == "cuda"), key=lambda r: (r["kind"], r["n"]))


def gpu_section(reference_dir, title, notes=None):
    """A report section on the stored GPU runs: (the records, the section's first lines); the
    lines say what to run where none are stored."""
    recs = gpu_runs(reference_dir, notes)
    lines = [f"## {title}", ""]
    if not recs:
        lines += [f"No GPU runs stored in `{reference_dir}/challenge/runs.json` yet (scripts/gpu/check.sh on a GPU "
                  "machine, then scripts/gpu/store.py; README, \"GPU\").", ""]
    return recs, lines


GPU_KIND = {"hardwall": "hard wall", "hardwall_plain": "hard wall, no preconditioner", "adhesive": "adhesion (plain)", "shape": "adhesion, shape (s = 1 case)"}


def gpu_row_head(r):
    """A stored GPU run's first two cells: the case and the grid."""
    if r["kind"].startswith("tabor_mu"):  # check.sh's tabor:N:MU, one point of the Tabor sweep
        return [f"Tabor sweep, μ_T = {r['kind'][len('tabor_mu'):]}", f"{r['n']}²"]
    return [GPU_KIND.get(r["kind"], r["kind"]), f"{r['n']}²"]
