"""The challenge report's distributions, spectrum and cross sections (items 1, 3, 4, 5, 9) at
the reference load, drawn with their bands and written as data/*.csv."""
from __future__ import annotations
import os

import numpy as np

from cmc.analysis import bands
from .challenge_runs import Run, _centers, _observables, _problem, _reference_load_runs, _stored
from .common import CHALLENGE, finite, fmt, get, label_axes, plt, savefig, write_csv
from .stored_distributions import draw_stored_curve, draw_stored_profiles


def _distribution_runs(runs, notes):
    """Per problem (with adhesion first), the run shown at the reference load with its observables,
    and the next finer grid's observables for the band: [(run, obs, step, finer)], finer = (run,
    obs, step) or None."""
    out = []
    for adhesive in (True, False):
        got = []
        for r, _ in _reference_load_runs(runs, adhesive):
            obs, st = _observables(r, notes)
            if obs:
                got.append((r, obs, st))
        if got:
            out.append(got[0] + (got[1] if len(got) > 1 else None,))
    return out


def profile_band(run: Run, key: str, y: np.ndarray, v: np.ndarray, yf: np.ndarray, vf: np.ndarray,
                 ) -> tuple[np.ndarray | None, float | None]:
    """(band, floor) of a cross-section profile v(y) (key cross_section_gap or _pressure) against the
    same case's profile (yf, vf) on the next finer grid: bands.profile_band, at least
    bands.profile_floor from the run's solver tolerance, rms height, E* and rms slope. (None, None)
    where the finer profile does not cover the line."""
    floor = bands.profile_floor(key, get(run.s, "case", "solver", "tolerance") or 0.0,
                                get(run.s, "surface_facts", "rms_height") or 0.0, run.Estar,
                                get(run.s, "case", "surface", "rms_gradient") or 1.0)
    b = bands.profile_band(y, v, yf, vf, floor)
    return (None, None) if b is None else (b, floor)


def _band_or_stored(c, d, finer_curve, finer_nx, logx, logy, reference_dir, quantity, adhesive):
    """(band, legend text, table text) of a curve (c, d) at the reference load: its change to the
    same case on the next finer grid when that run is here; (None, ...) otherwise (the stored
    reference is drawn beside it with its own band, draw_stored_curve)."""
    if finer_curve is not None:
        b = bands.refinement_band(c, d, finer_curve[0], finer_curve[1], logx, logy)
        if np.isfinite(b).any():
            return b, f"band: change to {finer_nx}²", f"|this − {finer_nx}²| at {int(np.isfinite(b).sum())} of {len(c)} points"
    return None, "", "– (no finer run of this case here)"


def _hist_figure(dists, key_edges, key_density, xscale, yscale, xunit, yunit, xlabel, ylabel, title, path,
                 data_dir, csv_names, csv_stem, reference_dir, extra=None):
    fig, ax = plt.subplots(figsize=(6, 4.4))
    rows, csvs = [], []

    def curve(obs):
        e, d = obs.get(key_edges), obs.get(key_density)
        if e is None or d is None or len(e) != len(d) + 1 or len(d) == 0:
            return None
        return _centers(e, xscale == "log"), d

    for r, obs, st, finer in dists:
        got = curve(obs)
        if got is None:
            continue
        c, d = got
        m = np.isfinite(d) & (d > 0 if yscale == "log" else np.isfinite(d)) & (c > 0 if xscale == "log" else True)
        line, = ax.plot(c[m] * xunit, d[m] * yunit, ".-", ms=3, lw=0.8,
                        label=f"{_problem(r)}: {r.label}, p = {st['p'] / 1e3:.4g} kPa")
        cols = [(csv_names[0], c[m]), (csv_names[1], d[m])]
        fc = curve(finer[1]) if finer else None
        b, legend, band_from = _band_or_stored(c[m], d[m], fc, finer[0].nx if finer else None, xscale == "log",
                                               yscale == "log", reference_dir, csv_stem, r.adhesive)
        if b is not None:
            ok = np.isfinite(b)
            lo = d[m] - np.where(ok, b, 0)
            if yscale == "log":
                lo = np.maximum(lo, d[m] * 1e-3)
            ax.fill_between(c[m] * xunit, lo * yunit, (d[m] + np.where(ok, b, 0)) * yunit, where=ok,
                            color=line.get_color(), alpha=0.2, lw=0, label=legend)
            cols.append((csv_names[1] + "_err", b))
        csv = os.path.join(data_dir, f"{csv_stem}__{r.tag()}.csv")
        write_csv(csv, cols, f"cmc challenge {csv_stem}: {r.name}, grid {r.nx}x{r.ny}, step at p = {st['p']:.6g} Pa\n"
                             "bin centres (geometric for log bins) and probability densities, SI"
                             + (f"; *_err: the band ({band_from}; nan: none there)" if len(cols) > 2 else ""))
        csvs.append(csv)
        e = obs[key_edges]
        rows.append([_problem(r), r.label, fmt(st["p"] / 1e3, 4), len(d), f"{fmt(e[0] * xunit, 3)} – {fmt(e[-1] * xunit, 3)}",
                     band_from])
    for ad in (True, False):
        rows += draw_stored_curve(ax, _stored(reference_dir, csv_stem, ad), ad, xunit, yunit, yscale == "log")
    if not rows:
        plt.close(fig)
        return None
    ax.set_xscale(xscale)
    ax.set_yscale(yscale)
    if extra:
        extra(ax)
    label_axes(ax, xlabel, ylabel, title)
    savefig(fig, path)
    return path, rows, csvs


def _spectrum(dists, out_dir, data_dir, reference_dir):
    fig, ax = plt.subplots(figsize=(6, 4.4))
    rows, csvs = [], []

    def curve(obs):
        q, C = obs.get("stress_spectrum_q"), obs.get("stress_spectrum_C")
        if q is None or C is None or len(q) != len(C) or len(q) == 0:
            return None
        m = (q > 0) & (C > 0) & np.isfinite(C)
        return q[m], C[m]

    for r, obs, st, finer in dists:
        got = curve(obs)
        if got is None:
            continue
        q, C = got
        line, = ax.loglog(q, C, ".-", ms=3, lw=0.8, label=f"{_problem(r)}: {r.label}, p = {st['p'] / 1e3:.4g} kPa")
        cols = [("q_per_m", q), ("C_Pa2m2", C)]
        fc = curve(finer[1]) if finer else None
        b, legend, band_from = _band_or_stored(q, C, fc, finer[0].nx if finer else None, True, True, reference_dir,
                                               "stress_spectrum", r.adhesive)
        if b is not None:
            ok = np.isfinite(b)
            ax.fill_between(q, np.maximum(C - np.where(ok, b, 0), C * 1e-3), C + np.where(ok, b, 0), where=ok,
                            color=line.get_color(), alpha=0.2, lw=0, label=legend)
            cols.append(("C_Pa2m2_err", b))
        csv = os.path.join(data_dir, f"stress_spectrum__{r.tag()}.csv")
        write_csv(csv, cols, f"cmc challenge stress spectrum: {r.name}, grid {r.nx}x{r.ny}, step at p = {st['p']:.6g} Pa\n"
                             "isotropic spectral density of the interfacial stress, integral d^2q C(q) = variance")
        csvs.append(csv)
        rows.append([_problem(r), r.label, fmt(st["p"] / 1e3, 4), len(q), f"{fmt(q.min(), 3)} – {fmt(q.max(), 3)}",
                     band_from])
    for ad in (True, False):
        rows += draw_stored_curve(ax, _stored(reference_dir, "stress_spectrum", ad), ad, 1.0, 1.0, True)
    if not rows:
        plt.close(fig)
        return None
    qr, qs = 2 * np.pi / CHALLENGE["lambda_r"], 2 * np.pi / CHALLENGE["lambda_s"]
    ax.axvline(qr, color="gray", ls=":", lw=0.8)
    ax.axvline(qs, color="gray", ls="--", lw=0.8)
    ax.text(qr, ax.get_ylim()[0], " q_r", fontsize=7, va="bottom")
    ax.text(qs, ax.get_ylim()[0], " q_s", fontsize=7, va="bottom")
    label_axes(ax, "wavenumber q (1/m)", "stress spectrum C_σ(q) (Pa² m²)", "5. interfacial stress spectrum")
    path = os.path.join(out_dir, "stress_spectrum.png")
    savefig(fig, path)
    return path, rows, csvs


def _zoom_centre(y, g, p):
    """Where the cross-section zoom is centred: at the largest tension (the adhesive neck at a
    contact line) if there is tension, else at the contact edge nearest the largest stress."""
    okg = g is not None and len(g) == len(y)
    okp = p is not None and len(p) == len(y)
    if okp and np.min(p) < 0:
        return y[int(np.argmin(p))]
    if not (okp or okg):
        return None
    i_max = int(np.argmax(p)) if okp else int(np.argmin(g))
    inside = (g <= 0) if okg else (p > 0)
    edges = np.nonzero(inside[1:] != inside[:-1])[0]
    return y[int(edges[np.argmin(np.abs(edges - i_max))])] if len(edges) else y[i_max]


def _cross_section(dists, out_dir, data_dir, reference_dir):
    have = [(r, o, st, f) for r, o, st, f in dists if "cross_section_y" in o and
            ("cross_section_gap" in o or "cross_section_pressure" in o)]
    if not have:
        return None
    # One zoom window for every run (the first run's, the adhesive one where there is one), so
    # that the panels compare the same 2 µm of the section.
    r0, o0 = have[0][0], have[0][1]
    yc = _zoom_centre(o0["cross_section_y"], o0.get("cross_section_gap"), o0.get("cross_section_pressure"))
    if yc is None:
        return None
    fig, axes = plt.subplots(2, 2, figsize=(11, 6.5))
    rows, csvs = [], []
    # Drawn adhesive first, then the hard wall on top, dashed and thinner, so that neither hides the other.
    styles = [dict(ls="-", lw=0.9, alpha=0.85, zorder=2), dict(ls="--", lw=0.7, color="k", zorder=3)]
    for k, (r, o, st, finer) in enumerate(have):
        y = o["cross_section_y"]
        lab = f"{_problem(r)}: {r.label}, p = {st['p'] / 1e3:.4g} kPa"
        sty = styles[min(k, 1)] if len(have) > 1 else styles[0]
        zoom = np.abs(y - yc) <= 1e-6
        cols, how = [("y_m", y)], []
        for row, key, col, scale in ((0, "cross_section_gap", "gap_m", (1e6, 1e9)),
                                     (1, "cross_section_pressure", "pressure_Pa", (1e-6, 1e-6))):
            v = o.get(key)
            if v is None or len(v) != len(y):
                continue
            line, = axes[row, 0].plot(y * 1e6, v * scale[0], label=lab, **sty)
            axes[row, 1].plot(y[zoom] * 1e6, v[zoom] * scale[1], marker=".", ms=2, **sty)
            cols.append((col, v))
            fo = finer[1] if finer else {}
            b, floor = (profile_band(r, key, y, v, fo["cross_section_y"], fo[key])
                        if "cross_section_y" in fo and key in fo else (None, None))
            if b is None:
                continue
            # The band is drawn in the zoom only: on the whole line it is a grid spacing wide.
            axes[row, 1].fill_between(y[zoom] * 1e6, (v - b)[zoom] * scale[1], (v + b)[zoom] * scale[1],
                                      color=line.get_color(), alpha=0.2, lw=0, step="mid",
                                      label=f"band: change to {finer[0].nx}²")
            cols.append((col + "_err", b))
            how.append(f"{col}: median {fmt(float(np.median(b)), 3)}, largest {fmt(float(np.max(b)), 3)}, "
                       f"floor {fmt(floor, 3)}")
        csv = os.path.join(data_dir, f"cross_section__{r.tag()}.csv")
        x0 = get(r.s, "case", "observables", "cross_section_x")
        write_csv(csv, cols, f"cmc challenge cross section x = {x0} m: {r.name}, grid {r.nx}x{r.ny}, "
                             f"step at p = {st['p']:.6g} Pa\n"
                             "checkable with: cmc check FILE --quantity cross_section_gap | cross_section_pressure"
                             + (f"\n*_err: the band, the largest |this - the same case on {finer[0].nx}^2| at the finer "
                                "points nearest each point, at least the solver's tolerance in the problem's scale" if how else ""))
        csvs.append(csv)
        rows.append([_problem(r), r.label, fmt(x0 * 1e6 if finite(x0) else None, 4), len(y),
                     "; ".join(how) if how else "– (no run of this case on a finer grid)"])
    for ad in (True, False):
        rows += draw_stored_profiles(axes[:, 1], [_stored(reference_dir, q, ad) for q in ("cross_section_gap",
                                                                                           "cross_section_pressure")], ad, yc)
    for a in axes[:, 1]:
        a.set_xlim((yc - 1e-6) * 1e6, (yc + 1e-6) * 1e6)
    axes[0, 0].set_ylabel("gap (µm)")
    axes[0, 1].set_ylabel("gap (nm)")
    axes[1, 0].set_ylabel("interfacial stress p (MPa, compressive > 0)")
    axes[1, 1].set_ylabel("p (MPa)")
    axes[0, 0].set_title("9. gap and stress along the cross section x = 50 µm", fontsize=10)
    axes[0, 1].set_title(f"zoom: y = {(yc - 1e-6) * 1e6:.4g} – {(yc + 1e-6) * 1e6:.4g} µm (one window for all runs)",
                         fontsize=9)
    for a in axes.ravel():
        a.set_xlabel("y (µm)")
        a.grid(True, alpha=0.3)
    axes[0, 0].legend(fontsize=7)
    axes[1, 0].legend(fontsize=7)
    path = os.path.join(out_dir, "cross_section.png")
    savefig(fig, path)
    return path, rows, csvs
