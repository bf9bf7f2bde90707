"""The challenge over many realisations of its spectrum: for each row of a curve (a load, or a
mu_T), the ensemble mean over surfaces, its standard error, and the spread of one realisation,
from runs that differ only in surface.seed (scripts/ensemble.py makes them, and
scripts/ensemble_store.py stores them in reference/challenge/ensemble/runs.json).

Three questions, three references (docs/user-guide/checking-predictions.md):
- "surface": cmc's own realisation (seed 28), the best estimates: numerical bands only;
- "ensemble": the mean over all surfaces of the spectrum, for a theory; band = the numerical
  error (transferred from seed 28's refinement) combined in quadrature with k times the standard
  error of the mean;
- "realisation": what a single surface of the spectrum gives, e.g. the organisers' own; band =
  the numerical error combined with k s sqrt(1 + 1/m) for m seeds of standard deviation s.

A prediction is scored at every row at once, so k is a simultaneous factor, not Student's
pointwise t: each seed's largest standardised deviation over the curve's rows, z = max |v - mean|
/ s, and k the ceil(0.95 (m + 1))-th smallest of the m values of z. A new surface's z lies below
it with probability at least 95 % (the distribution-free prediction bound of order statistics,
P(Z_new <= Z_(k)) = k / (m + 1); Wilks, Ann. Math. Statist. 12, 91 (1941)), so its whole curve
lies inside the band. The mean's own deviation, in units of its standard error, is such a z too
(central limit theorem), and takes the same k.

The ensemble's runs are made on a coarser grid than the best estimates (2048²). Each row's value
is carried to the best estimate's grid by seed 28's own factor, best estimate / seed 28's value
on the ensemble's grid (the grid correction), whose error is the best estimate's relative error;
transfer_check tests that a grid's factor is the same on other seeds.
"""
import math
from dataclasses import dataclass
from typing import Dict, Iterable, List, Optional, Sequence, Tuple

Z975 = 1.959963984540054  # the standard normal's 97.5 % quantile
OWN_SEED = 28  # cmc's own realisation (cases/challenge/challenge-base.toml)


def t975(df: int) -> float:
    """Student's t 97.5 % quantile for df degrees of freedom, by the Cornish-Fisher expansion
    (Abramowitz & Stegun 26.7.5), within 2e-4 of the exact value for df >= 5."""
    if df < 1:
        raise ValueError("t975 needs at least one degree of freedom")
    z = Z975
    g1 = (z ** 3 + z) / 4
    g2 = (5 * z ** 5 + 16 * z ** 3 + 3 * z) / 96
    g3 = (3 * z ** 7 + 19 * z ** 5 + 17 * z ** 3 - 15 * z) / 384
    g4 = (79 * z ** 9 + 776 * z ** 7 + 1482 * z ** 5 - 1920 * z ** 3 - 945 * z) / 92160
    return z + g1 / df + g2 / df ** 2 + g3 / df ** 3 + g4 / df ** 4


@dataclass(frozen=True)
class RowStats:
    """One row over the seeds: m values, their mean, standard deviation (m - 1), the standard
    error of the mean, and the half-width of the 95 % prediction interval for one more surface."""
    x: float
    m: int
    mean: float
    std: float
    stderr: float
    prediction: float
    seeds: Tuple[int, ...]


def row_stats(x: float, values: Dict[int, float]) -> Optional[RowStats]:
    """The statistics of one row from {seed: value}; None with fewer than 3 finite values."""
    vals = {s: v for s, v in values.items() if isinstance(v, (int, float)) and math.isfinite(v)}
    m = len(vals)
    if m < 3:
        return None
    mean = sum(vals.values()) / m
    std = math.sqrt(sum((v - mean) ** 2 for v in vals.values()) / (m - 1))
    return RowStats(x=x, m=m, mean=mean, std=std, stderr=std / math.sqrt(m),
                    prediction=t975(m - 1) * std * math.sqrt(1 + 1 / m), seeds=tuple(sorted(vals)))


def _same(a: float, b: float, tol: float = 0.01) -> bool:
    return abs(a / b - 1) <= tol if b else a == b


def table(records: Iterable[dict], key: str, x_key: str, seeds: Optional[Sequence[int]] = None
          ) -> List[Tuple[float, Dict[int, float]]]:
    """[(x, {seed: value})] of converged points, x ascending (points within 1 % are one row):
    x_key "pressure_Pa" takes every step of the records' load sweeps, "tabor" each record's
    mu_T; key is a record key ("a_r", "a_rep", "mean_gap_m", or "mean_gap_over_h_rms")."""
    rows: List[Tuple[float, Dict[int, float]]] = []
    for r in records:
        seed = (r.get("physics") or {}).get("surface.seed")
        if seed is None or (seeds is not None and seed not in seeds):
            continue
        for pt in _points(r):
            if not pt.get("converged") or pt.get(x_key) is None:
                continue
            v = _value(pt, r, key)
            if v is None:
                continue
            row = next((vals for x, vals in rows if _same(pt[x_key], x)), None)
            if row is None:
                row = {}
                rows.append((pt[x_key], row))
            row[seed] = v
    return sorted(rows, key=lambda xr: xr[0])


def _points(r: dict) -> List[dict]:
    """A record's points: its sweep's steps, or the run itself."""
    if r.get("steps"):
        return [dict(s, tabor=r.get("tabor")) for s in r["steps"]]
    return [{"pressure_Pa": r.get("pressure_Pa"), "tabor": r.get("tabor"), "a_r": r.get("a_r"),
             "a_rep": r.get("a_rep"), "mean_gap_m": r.get("mean_gap_m"), "converged": r.get("status") == "converged"}]


def _value(pt: dict, r: dict, key: str) -> Optional[float]:
    if key == "mean_gap_over_h_rms":
        g, h = pt.get("mean_gap_m"), r.get("rms_height_m")
        return g / h if g is not None and h else None
    return pt.get(key)


def stats(records: Iterable[dict], key: str, x_key: str, seeds: Optional[Sequence[int]] = None) -> List[RowStats]:
    """row_stats of every row of table()."""
    out = [row_stats(x, vals) for x, vals in table(list(records), key, x_key, seeds)]
    return [s for s in out if s is not None]


@dataclass(frozen=True)
class Correction:
    """The grid correction of one row: the factor best / own, and its relative error."""
    x: float
    factor: float
    relative_error: float
    own: float
    best: float


def correction(x: float, own: Optional[float], best: Optional[float], best_error: Optional[float]
               ) -> Optional[Correction]:
    """The factor that carries seed 28's value on the ensemble's grid (own) to its best estimate
    (best +- best_error); None where a value is missing or own is 0."""
    if own is None or best is None or best_error is None or not own:
        return None
    return Correction(x=x, factor=best / own, relative_error=abs(best_error / best) if best else 0.0,
                      own=own, best=best)


@dataclass(frozen=True)
class Row:
    """One row of an ensemble or realisation reference: x, value and band half-width, and how the
    band is made (relative parts)."""
    x: float
    value: float
    band: float
    numerical: float
    statistical: float
    m: int


def simultaneous_factor(rows: Sequence[Tuple[float, Dict[int, float]]], stats_: Sequence[RowStats],
                        coverage: float = 0.95) -> Optional[float]:
    """k of the module's doc: the ceil(coverage (m + 1))-th smallest of the seeds' largest
    standardised deviations over the rows (table() rows, their row_stats), the largest where that
    rank exceeds m; None with fewer than 3 seeds."""
    by_x = {s.x: s for s in stats_}
    z: Dict[int, float] = {}
    for x, vals in rows:
        st = next((s for sx, s in by_x.items() if _same(sx, x)), None)
        if st is None or not st.std:
            continue
        for seed, v in vals.items():
            if seed in st.seeds:
                z[seed] = max(z.get(seed, 0.0), abs(v - st.mean) / st.std)
    if len(z) < 3:
        return None
    ordered = sorted(z.values())
    k = math.ceil(coverage * (len(ordered) + 1))
    return ordered[min(k, len(ordered)) - 1]


def reference_rows(rows: Sequence[RowStats], corrections: Sequence[Correction], question: str,
                   factor: Optional[float] = None) -> List[Row]:
    """The rows of the "ensemble" or "realisation" reference: each row's mean times its grid
    correction; band = value x (the correction's relative error) (+) the statistical half-width
    (factor standard errors, or factor s sqrt(1 + 1/m)), combined in quadrature; factor None:
    pointwise, 2 for the ensemble and the row's prediction interval for a realisation. Rows
    without a correction at their x are left out."""
    if question not in ("ensemble", "realisation"):
        raise ValueError(f"question {question!r}: expected ensemble or realisation")
    out = []
    for s in rows:
        c = next((c for c in corrections if _same(c.x, s.x)), None)
        if c is None or not s.mean:
            continue
        value = s.mean * c.factor
        if factor is None:
            half = 2 * s.stderr if question == "ensemble" else s.prediction
        else:
            half = factor * (s.stderr if question == "ensemble" else s.std * math.sqrt(1 + 1 / s.m))
        stat = half / abs(s.mean)
        rel = math.hypot(c.relative_error, stat)
        out.append(Row(x=s.x, value=value, band=rel * abs(value), numerical=c.relative_error, statistical=stat, m=s.m))
    return out


def transfer_check(ratios: Dict[int, float], own_seed: int = OWN_SEED) -> Optional[dict]:
    """Whether a refinement factor (fine / coarse value of one row) measured on seed 28 holds on
    other seeds: {seed: ratio} with seed 28 among them. Returns the largest relative difference
    of another seed's factor from seed 28's, or None without seed 28 and one other seed."""
    if own_seed not in ratios or len(ratios) < 2:
        return None
    own = ratios[own_seed]
    diffs = {s: abs(r / own - 1) for s, r in ratios.items() if s != own_seed}
    worst = max(diffs, key=lambda s: diffs[s])
    return {"own": own, "others": {s: ratios[s] for s in diffs}, "largest": diffs[worst], "seed": worst}


# The reference load's quantities: (name, record key, best-estimate quantity).
HEADLINE = (("a_r", "a_r", "a_r"), ("a_rep", "a_rep", "a_rep"), ("mean_gap", "mean_gap_m", "mean_gap"))


def reference_load_questions(records: Sequence[dict], estimate: Optional[dict], seeds: Sequence[int],
                             p_tilde: float, transfer: Optional[Dict[str, List[dict]]] = None) -> Dict[str, dict]:
    """The headline's three answers at the reference load for one problem: records are the
    ensemble's 250 kPa runs of that problem, estimate its best estimate (best_estimates.json's
    reference_load entry). Per quantity (and kappa = a_r / p_tilde, and the mean gap over the rms
    height, which transfers best between surfaces): "surface" (the best estimate), "ensemble" and
    "realisation" ({value, band, m}; pointwise: one number is scored here, 2 standard errors and
    the row's prediction interval), each carried to the best estimate's grid by seed 28's
    correction, for the ensemble and realisation widened by the surfaces' spread of its refinement
    factor where transfer ({record key: transfer_rows}) measured it. {} without a best estimate."""
    if not estimate:
        return {}
    out: Dict[str, dict] = {}
    for name, key, short in HEADLINE + (("mean_gap_over_h_rms", "mean_gap_over_h_rms", "mean_gap"),):
        q = estimate["quantities"].get(short)
        rows = table(records, key, "pressure_Pa", seeds)
        if not q or q.get("error") is None or len(rows) != 1:
            continue
        _, vals = rows[0]
        own = table(records, key, "pressure_Pa", [OWN_SEED])
        st = row_stats(rows[0][0], vals)
        own_v = own[0][1].get(OWN_SEED) if own else None
        own_best = q["value"] if key != "mean_gap_over_h_rms" else _scaled_best(q, records)
        c = correction(rows[0][0], own_v, own_best, abs(own_best) * (q["relative_error"] or 0.0))
        if st is None or c is None:
            continue
        entry = {"surface": {"value": own_best, "band": c.relative_error * abs(own_best)}}
        carried = with_transfer(c, (transfer or {}).get(key, []))  # other surfaces: their spread too
        for question in ("ensemble", "realisation"):
            r = reference_rows([st], [carried], question)[0]
            entry[question] = {"value": r.value, "band": r.band, "m": r.m}
        out[name] = entry
    if "a_r" in out:
        out["kappa"] = {k: {kk: (vv / p_tilde if kk in ("value", "band") else vv) for kk, vv in v.items()}
                        for k, v in out["a_r"].items()}
    return out


def _scaled_best(q: dict, records: Sequence[dict]) -> float:
    """Seed 28's best mean gap over its rms height (the height is the surface's, grid-independent)."""
    h = next((r.get("rms_height_m") for r in records if (r.get("physics") or {}).get("surface.seed") == OWN_SEED), None)
    return q["value"] / h if h else math.nan


def transfer_rows(coarse: Sequence[Tuple[float, Dict[int, float]]], fine: Sequence[Tuple[float, Dict[int, float]]]
                  ) -> List[dict]:
    """Whether a grid correction measured on seed 28 holds on other surfaces: per row (table()
    rows of one quantity on a grid and on the next finer one), each seed's refinement factor
    fine / coarse and transfer_check of them. Rows where seed 28 and one other seed have both."""
    out = []
    for x, vf in fine:
        vc = next((v for cx, v in coarse if _same(cx, x)), None)
        if vc is None:
            continue
        ratios = {s: vf[s] / vc[s] for s in vf if s in vc and vc[s]}
        got = transfer_check(ratios)
        if got is not None:
            out.append(dict(got, x=x))
    return out


def with_transfer(c: Correction, transfer: Sequence[dict]) -> Correction:
    """The correction with the surfaces' spread of its refinement factor added: twice the largest
    relative difference of another seed's factor from seed 28's at its row (the whole correction,
    from the ensemble's grid to the converged value, is about twice the first doubling's for the
    counted area's first order), in quadrature with its own error. Unchanged where not measured."""
    t = next((t for t in transfer if _same(t["x"], c.x)), None)
    if t is None:
        return c
    return Correction(x=c.x, factor=c.factor, relative_error=math.hypot(c.relative_error, 2 * t["largest"]),
                      own=c.own, best=c.best)
