#!/usr/bin/python3
"""Overlay figure for `cmc check`: prediction vs reference, and the difference.

usage: /usr/bin/python3 reports/plot_check.py DIR/check.json DIR/check.png

Reads check.json written by `cmc check --out DIR` (prediction and reference points in
SI units, the evaluation points, metrics and verdict) and draws the two curves in the
representation the challenge asks for (log axes where it says so), the common range
shaded, and below them the difference in that representation (decades on a log y axis,
difference / max|y_ref| on a linear one).
Exit codes: 0 ok, 2 bad arguments or input, 3 matplotlib/numpy missing.
"""
import json
import math
import sys


def axis_label(a):
    u = a["unit"]
    return a["label"] + ("" if u in ("1", "as in the files") else f" ({u})")


def draw_curves(top, bot, c, logx, logy):
    """The top panel: reference (with its band) and prediction; the common range shaded on both."""
    ref, pred, ev = c["reference"], c["prediction"], c["evaluation"]

    def keep(xs, ys):
        pts = [(x, y) for x, y in zip(xs, ys) if (not logx or x > 0) and (not logy or y > 0)]
        return [p[0] for p in pts], [p[1] for p in pts]

    rx, ry = keep(ref["x"], ref["y"])
    px, py = keep(pred["x"], pred["y"])
    top.plot(rx, ry, "-", color="black", lw=1.5, label="reference: " + (c.get("reference_name") or "reference"))
    top.plot(px, py, "o", ms=3.5, color="tab:red", mfc="none", label="prediction")
    # The reference's own error band, where it has one (at the evaluation points).
    elo, ehi = ev.get("reference_low") or [], ev.get("reference_high") or []
    if elo and len(elo) == len(ev["x"]):
        top.fill_between(ev["x"], [max(v, 1e-300) if logy else v for v in elo], ehi, color="gray", alpha=0.3,
                         lw=0, label="reference error band")
    lo, hi = c["common_range"]
    for a in (top, bot):
        a.axvspan(lo, hi, color="tab:blue", alpha=0.07, lw=0)
        if logx:
            a.set_xscale("log")
    if logy:
        top.set_yscale("log")
    top.set_ylabel(axis_label(c["axes"]["y"]))
    top.legend(loc="best", fontsize=8)
    v = c["verdict"]
    top.set_title(f"{c.get('title', c['quantity'])}\n{'PASS' if v['pass'] else 'FAIL'}: "
                  f"{v['metric']} = {v['value']:.3g} (tolerance {v['tolerance']:.3g})", fontsize=10)


def draw_difference(bot, c, logy):
    """The bottom panel: the difference in the representation, with the tolerance band."""
    ev, v = c["evaluation"], c["verdict"]
    elo, ehi = ev.get("reference_low") or [], ev.get("reference_high") or []
    # Difference in the representation.
    ex, ep, er = ev["x"], ev["prediction"], ev["reference"]
    m = c["metrics"]
    if logy:
        d = [math.log10(p / r) for p, r in zip(ep, er)]
        bot.set_ylabel("log10(pred/ref)\n(decades)")
    else:
        s = m.get("rel_scale") or 1.0
        d = [(p - r) / s for p, r in zip(ep, er)]
        bot.set_ylabel("(pred - ref)\n/ max|ref|")
    bot.plot(ex, d, ".-", color="tab:red", ms=3, lw=0.8)
    bot.axhline(0, color="black", lw=0.8)
    # The tolerance band where the metric is a bound on the plotted difference.
    tol = v["tolerance"]
    band = None
    if v["metric"] == "max_band" and elo and len(elo) == len(ex):
        if logy:
            lo_d = [math.log10(l / r) if l > 0 else -1e300 for l, r in zip(elo, er)]
            hi_d = [math.log10(h / r) for h, r in zip(ehi, er)]
        else:
            s = m.get("rel_scale") or 1.0
            lo_d = [(l - r) / s for l, r in zip(elo, er)]
            hi_d = [(h - r) / s for h, r in zip(ehi, er)]
        lo_d = [max(x, min(d) - 1) if x == -1e300 else x for x in lo_d]
        bot.fill_between(ex, lo_d, hi_d, color="gray", alpha=0.3, lw=0)
    elif v["metric"].startswith("max_"):
        if logy:
            band = (tol, -tol) if v["metric"] == "max_abs" else (math.log10(1 + tol), math.log10(max(1 - tol, 1e-300)))
        elif v["metric"] == "max_rel":
            band = (tol, -tol)
        else:
            s = m.get("rel_scale") or 1.0
            band = (tol / s, -tol / s)
    if band:
        for b in band:
            bot.axhline(b, color="gray", ls="--", lw=0.8)
    bot.set_xlabel(axis_label(c["axes"]["x"]))


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as e:  # pragma: no cover - depends on the machine
        print(f"plot_check.py: matplotlib is missing ({e}); install python3-matplotlib", file=sys.stderr)
        return 3
    try:
        with open(argv[1]) as f:
            c = json.load(f)
    except (OSError, ValueError) as e:
        print(f"plot_check.py: cannot read {argv[1]}: {e}", file=sys.stderr)
        return 2

    ax_x, ax_y = c["axes"]["x"], c["axes"]["y"]
    logx, logy = bool(ax_x["log"]), bool(ax_y["log"])
    fig, (top, bot) = plt.subplots(2, 1, figsize=(6.4, 6.4), sharex=True,
                                   gridspec_kw={"height_ratios": [3, 1.3]})
    draw_curves(top, bot, c, logx, logy)
    draw_difference(bot, c, logy)
    m = c["metrics"]
    fig.text(0.01, 0.005, f"max abs {m['max_abs']:.3g}, rms abs {m['rms_abs']:.3g} ({m['abs_unit']}); "
             f"max rel {m['max_rel']:.3g}, rms rel {m['rms_rel']:.3g}; {c['representation']}",
             fontsize=7, color="dimgray")
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    try:
        fig.savefig(argv[2], dpi=120)
    except OSError as e:
        print(f"plot_check.py: cannot write {argv[2]}: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
