"""reports/validation/: the validation suite's pass/fail table (index.md), one
error-vs-grid-spacing plot per refinement study (with the observed order), and the
solved pressure/gap profiles against the analytic curves (result.h5 fields against
the stored reference CSVs in reference/).

Input: <validation dir>/<case>/summary.json (+ result.h5) as written by
`cmc validate CASE.toml --out <validation dir>` (ctest writes build/validation/).
"""
import math
import os

import numpy as np

from common import (fmt, get, h5_open, load_json, md_table, plt, read_reference_csv, rel, savefig,
                    step_groups, case_name)


def _collect(validation_dirs, notes):
    """{case name: (summary, folder)}; the newest summary wins when a case appears in
    several folders."""
    runs = {}
    for d in validation_dirs:
        if not os.path.isdir(d):
            continue
        for name in sorted(os.listdir(d)):
            f = os.path.join(d, name, "summary.json")
            if not os.path.isfile(f):
                continue
            s = load_json(f, notes)
            if not isinstance(s, dict):
                continue
            key = case_name(s) or name
            t = os.path.getmtime(f)
            if key not in runs or t > runs[key][2]:
                runs[key] = (s, os.path.dirname(f), t)
    return {k: (v[0], v[1]) for k, v in runs.items()}


def _refinement_plot(case, entry, summary, out_dir):
    grids = entry.get("grids") or []
    errors = entry.get("errors") or []
    if len(grids) < 2 or len(grids) != len(errors):
        return None
    size = get(summary, "grid", "size_x") or get(summary, "case", "grid", "size") or 1.0
    dx = np.array([size / g for g in grids], dtype=float)
    err = np.array(errors, dtype=float)
    ok = (dx > 0) & (err > 0)
    if ok.sum() < 2:
        return None
    order = entry.get("observed_order")
    min_order = entry.get("min_order")
    fig, ax = plt.subplots(figsize=(5.2, 4.2))
    ax.loglog(dx[ok] * 1e6, err[ok], "o-", color="tab:blue", label="cmc")
    for g, x, e in zip(grids, dx, err):
        if x > 0 and e > 0:
            ax.annotate(f"{g}", (x * 1e6, e), textcoords="offset points", xytext=(4, 4), fontsize=7)
    # Guides through the least-squares centroid: the observed and the required order.
    x0, e0 = math.exp(np.mean(np.log(dx[ok]))), math.exp(np.mean(np.log(err[ok])))
    xs = np.array([dx[ok].min(), dx[ok].max()])
    if order is not None and math.isfinite(order):
        ax.loglog(xs * 1e6, e0 * (xs / x0) ** order, "--", color="tab:blue", lw=0.8,
                  label=f"observed order {order:.2f}")
    if min_order is not None:
        ax.loglog(xs * 1e6, e0 * (xs / x0) ** min_order, ":", color="gray", lw=0.8,
                  label=f"required order {min_order:g}")
    q = entry.get("quantity", "order(?)")
    inner = q[len("order("):-1] if q.startswith("order(") else q
    ax.set_xlabel("grid spacing dx (µm)")
    ax.set_ylabel(f"error of {inner} (as defined in the check)")
    ax.set_title(f"{case}: {q} — {'pass' if entry.get('pass') else 'FAIL'}", fontsize=10)
    ax.legend(fontsize=8)
    ax.grid(True, which="both", alpha=0.3)
    path = os.path.join(out_dir, f"refinement_{case}.png")
    savefig(fig, path)
    return path


def _hertz_profiles(case, summary, folder, ref_dir, out_dir, notes):
    """p/p0 and gap against r/a for every step, on Hertz's curves."""
    h5 = h5_open(os.path.join(folder, "result.h5"), notes)
    if h5 is None:
        return None
    Es = get(summary, "case", "material", "contact_modulus")
    R = get(summary, "case", "surface", "radius")
    if not Es or not R:
        return None
    dx = get(summary, "grid", "dx")
    dy = get(summary, "grid", "dy")
    steps = summary.get("steps") or []
    ref = read_reference_csv(os.path.join(ref_dir, "hertz_pressure_profile.csv"))
    with h5:
        heights = h5["heights"][()]
        iy0, ix0 = np.unravel_index(np.argmin(heights), heights.shape)
        ny, nx = heights.shape
        X = (np.arange(nx) - ix0) * dx
        Y = (np.arange(ny) - iy0) * dy
        r = np.hypot(*np.meshgrid(X, Y))
        fig, (a1, a3, a2) = plt.subplots(1, 3, figsize=(15, 4.2))
        for k, g in enumerate(step_groups(h5)):
            F = steps[k]["force"] if k < len(steps) else None
            if not F or F <= 0:
                continue
            a = (3 * F * R / (4 * Es)) ** (1 / 3)
            p0 = 2 * Es * a / (math.pi * R)
            delta = a * a / R
            p = h5[g]["pressure"][()]
            gap = h5[g]["gap"][()]
            m = r.ravel() < 1.5 * a
            a1.plot(r.ravel()[m] / a, p.ravel()[m] / p0, ".", ms=2, alpha=0.5,
                    label=f"cmc, F = {F:.3g} N (a/dx = {a / dx:.1f})")
            s_ = r.ravel()[m] / a
            p_h = np.sqrt(np.clip(1 - s_ * s_, 0, None))  # Hertz, p/p0 (Johnson 1985 eq. 4.22)
            a3.plot(s_, p.ravel()[m] / p0 - p_h, ".", ms=2, alpha=0.5, label=f"F = {F:.3g} N")
            m2 = r.ravel() < 3 * a
            a2.plot(r.ravel()[m2] / a, gap.ravel()[m2] / delta, ".", ms=2, alpha=0.5, label=f"cmc, F = {F:.3g} N")
        if ref is not None:
            _, names, data = ref
            a1.plot(data[:, 0], data[:, 1], "-", color="black", lw=1.2, label="Hertz (reference/hertz_pressure_profile.csv)")
        # Hertz gap outside the contact (Johnson 1985 eq. 3.42b), in units of delta = a^2/R:
        # g/delta = (s^2/2 - 1) + ((2 - s^2) asin(1/s) + sqrt(s^2 - 1))/pi, s = r/a.
        s = np.linspace(1.0, 3.0, 200)
        g_ref = (s * s / 2 - 1) + ((2 - s * s) * np.arcsin(1 / s) + np.sqrt(s * s - 1)) / math.pi
        a2.plot(np.r_[0, 1, s], np.r_[0, 0, g_ref], "-", color="black", lw=1.2,
                label="Hertz, half-space (Johnson 1985 eq. 3.42)")
        a3.axhline(0, color="black", lw=0.8)
        a3.set_xlabel("r / a")
        a3.set_ylabel("(p − p_Hertz) / p0")
        a3.set_title(f"{case}: pressure error", fontsize=10)
        a3.legend(fontsize=7)
        a1.set_xlabel("r / a")
        a1.set_ylabel("p / p0")
        a1.set_title(f"{case}: pressure profile", fontsize=10)
        a1.legend(fontsize=7)
        a2.set_xlabel("r / a")
        a2.set_ylabel("gap / δ  (δ = a²/R)")
        a2.set_title(f"{case}: gap profile" + (" (periodic cell: image terms not in the curve)"
                                               if get(summary, "grid", "boundary") == "periodic" else ""), fontsize=9)
        a2.legend(fontsize=7)
    path = os.path.join(out_dir, f"profiles_{case}.png")
    savefig(fig, path)
    return path


def _westergaard_profiles(case, summary, folder, ref_dir, out_dir, notes):
    h5 = h5_open(os.path.join(folder, "result.h5"), notes)
    if h5 is None:
        return None
    Es = get(summary, "case", "material", "contact_modulus")
    h = get(summary, "case", "surface", "amplitude")
    lam = get(summary, "case", "surface", "wavelength") or get(summary, "grid", "size_x")
    dx = get(summary, "grid", "dx")
    if not Es or not h or not lam:
        return None
    pstar = math.pi * Es * h / lam
    steps = summary.get("steps") or []
    prof = read_reference_csv(os.path.join(ref_dir, "westergaard_pressure_profile.csv"))
    gapref = read_reference_csv(os.path.join(ref_dir, "westergaard_mean_gap.csv"))
    with h5:
        heights = h5["heights"][()].ravel()
        i0 = int(np.argmin(heights))
        n = heights.size
        x = ((np.arange(n) - i0) * dx) / lam
        x = (x + 0.5) % 1.0 - 0.5
        order = np.argsort(x)
        fig, (a1, a3, a2) = plt.subplots(1, 3, figsize=(15, 4.2))
        colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
        for k, g in enumerate(step_groups(h5)):
            pbar = steps[k]["mean_pressure"] if k < len(steps) else None
            if pbar is None:
                continue
            c = colors[k % len(colors)]
            p = h5[g]["pressure"][()].ravel()
            a1.plot(x[order], p[order] / pstar, ".", ms=2, color=c, label=f"cmc, pbar/p* = {pbar / pstar:.2f}")
            t = pbar / pstar
            curve = None
            if prof is not None:
                _, names, data = prof
                for j, nm in enumerate(names):
                    if nm.startswith("p_over_pstar_at_") and abs(float(nm.split("_at_")[1]) - t) < 1e-6:
                        curve = (data[:, 0], data[:, j])
            if curve is None and 0 < t < 1:  # closed form (Westergaard 1939)
                xs = np.linspace(-0.5, 0.5, 401)
                s2 = np.sin(np.pi * xs) ** 2
                curve = (xs, np.where(s2 < t, 2 * np.cos(np.pi * xs) * np.sqrt(np.clip(t - s2, 0, None)), 0.0))
            if curve is not None:
                a1.plot(curve[0], curve[1], "--", color="black", lw=0.8, zorder=5)
            if 0 < t < 1:  # error against the closed form at the grid points
                s2 = np.sin(np.pi * x) ** 2
                p_w = np.where(s2 < t, 2 * np.cos(np.pi * x) * np.sqrt(np.clip(t - s2, 0, None)), 0.0)
                a3.plot(x[order], (p / pstar - p_w)[order], ".", ms=2, color=c, label=f"pbar/p* = {t:.2f}")
        a1.plot([], [], "--", color="black", lw=0.8, label="Westergaard (reference/westergaard_pressure_profile.csv)")
        a3.axhline(0, color="black", lw=0.8)
        a3.set_xlabel("x / λ")
        a3.set_ylabel("(p − p_Westergaard) / p*")
        a3.set_title(f"{case}: pressure error", fontsize=10)
        a3.legend(fontsize=7)
        a1.set_xlabel("x / λ (from the contact centre)")
        a1.set_ylabel("p / p*   (p* = π E* h / λ)")
        a1.set_title(f"{case}: pressure profiles", fontsize=10)
        a1.legend(fontsize=7)
        if gapref is not None:
            _, names, data = gapref
            a2.semilogx(data[:, 0], data[:, 1], "-", color="black", lw=1.2,
                        label="Westergaard (reference/westergaard_mean_gap.csv)")
        pts = [(s["mean_pressure"] / pstar, s["mean_gap"] / h) for s in steps
               if s.get("mean_pressure", 0) > 0 and "mean_gap" in s]
        if pts:
            a2.semilogx([q[0] for q in pts], [q[1] for q in pts], "o", color="tab:red", mfc="none", label="cmc")
        a2.set_xlabel("pbar / p*")
        a2.set_ylabel("mean gap / h")
        a2.set_title(f"{case}: mean gap vs mean pressure", fontsize=10)
        a2.legend(fontsize=7)
    path = os.path.join(out_dir, f"profiles_{case}.png")
    savefig(fig, path)
    return path


def build(validation_dirs, ref_dir, out_dir, notes):
    os.makedirs(out_dir, exist_ok=True)
    runs = _collect(validation_dirs, notes)
    lines = ["# Validation report", ""]
    if not runs:
        lines += ["No validation results found in " + ", ".join(f"`{d}`" for d in validation_dirs) + ".",
                  "", "Run `scripts/test.sh -L validation` (writes build/validation/) or "
                  "`build/cmc validate cases/validation/*.toml --out build/validation`, then `scripts/report.sh`.", ""]
        return "\n".join(lines)
    rows, ref_rows, figures = [], [], []
    n_pass = n_fail = 0
    for case in sorted(runs):
        s, folder = runs[case]
        checks = s.get("validation")
        if not isinstance(checks, list) or not checks:
            rows.append([case, "–", "no \"validation\" entry in summary.json", "", "", "not checked"])
            continue
        for e in checks:
            if not isinstance(e, dict):
                continue
            ok = bool(e.get("pass"))
            n_pass += ok
            n_fail += not ok
            if "grids" in e:
                p = _refinement_plot(case, e, s, out_dir)
                ref_rows.append([case, e.get("quantity", ""), ", ".join(str(g) for g in e.get("grids", [])),
                                 ", ".join(fmt(x, 3) for x in e.get("errors", [])), fmt(e.get("observed_order"), 3),
                                 fmt(e.get("min_order"), 3), "pass" if ok else "**FAIL**",
                                 f"[plot]({os.path.basename(p)})" if p else "–"])
                if p:
                    figures.append((f"{case}: refinement", p))
            else:
                rows.append([case, e.get("quantity", ""), e.get("definition", ""), fmt(e.get("error"), 4),
                             fmt(e.get("tolerance"), 3), "pass" if ok else "**FAIL**"])
        ref = get(s, "case", "validation", "reference") or (checks[0].get("reference") if checks else None)
        try:
            if ref in ("hertz", "hertz_periodic"):
                p = _hertz_profiles(case, s, folder, ref_dir, out_dir, notes)
            elif ref == "westergaard":
                p = _westergaard_profiles(case, s, folder, ref_dir, out_dir, notes)
            else:
                p = None
        except (KeyError, ValueError, OSError) as err:
            notes.append(f"{case}: profiles not drawn ({err})")
            p = None
        if p:
            figures.append((f"{case}: profiles vs analytic", p))
    lines.append(f"**{n_pass} checks pass, {n_fail} fail** "
                 f"(from {', '.join('`' + d + '`' for d in validation_dirs if os.path.isdir(d))}).")
    lines += ["", "## Checks", "", md_table(["case", "quantity", "error definition", "error", "tolerance", "result"], rows)]
    if ref_rows:
        lines += ["", "## Refinement studies", "",
                  "Each case re-run on several grids; the observed order is the least-squares slope of "
                  "−log(error) against log(n).", "",
                  md_table(["case", "study", "grids n", "errors", "observed order", "required", "result", "figure"],
                           ref_rows)]
    if figures:
        lines += ["", "## Figures", ""]
        for title, p in figures:
            lines += [f"### {title}", "", f"![{title}]({rel(p, out_dir)})", ""]
    lines += ["", "## Runs", "",
              md_table(["case", "folder", "grid", "status", "wall time (s)", "FFT pairs"],
                       [[c, f"`{runs[c][1]}`",
                         f"{get(runs[c][0], 'grid', 'nx')}×{get(runs[c][0], 'grid', 'ny')}",
                         runs[c][0].get("status", "?"), fmt(get(runs[c][0], 'timing', 'wall_s'), 3),
                         fmt(get(runs[c][0], 'timing', 'fft_pairs'))] for c in sorted(runs)])]
    return "\n".join(lines) + "\n"
