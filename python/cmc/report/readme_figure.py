"""The README's first figure: the stored interfacial stress distribution at 250 kPa (challenge
item 4) with and without adhesion, each with its band and its grid, as reference/challenge/ and
its adhesionless/ store them (scripts/challenge_reference.py writes those files; nothing is
computed here).

    /usr/bin/python3 scripts/readme_figure.py [--ref reference/challenge] [--out reports/readme/stress_distribution.png]
"""
import argparse
import os
import sys
from typing import List, Optional

from cmc.analysis.runs import REPO as ROOT  # the checkout, through the build tree's links
from cmc.reference_files import read_curve
from cmc.report.stored_distributions import grid_name

QUANTITY = "stress_distribution"


def draw(ref_dir: str, out: str) -> None:
    """Both stored curves, stress in MPa against density in 1/MPa on a log axis, bands shaded."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    for folder, words, colour in ((os.path.join(ref_dir, "adhesionless"), "hard wall", "tab:blue"),
                                  (ref_dir, "with adhesion (μ_T = 3)", "tab:orange")):
        c = read_curve(os.path.join(folder, QUANTITY + ".csv"))
        if c is None:
            raise FileNotFoundError(os.path.join(folder, QUANTITY + ".csv"))
        cols = {col[0]: col[3] for col in c["columns"]}
        x = [v / 1e6 for v in cols[c["x"]]]
        y = [v * 1e6 for v in cols[c["y"]]]
        err = [v * 1e6 for v in cols[c["band"]]] if c.get("band") else [0.0] * len(y)
        lo = [max(v - e, v * 1e-3) for v, e in zip(y, err)]
        ax.fill_between(x, lo, [v + e for v, e in zip(y, err)], color=colour, alpha=0.25, linewidth=0)
        ax.plot(x, y, color=colour, label=f"{words}, {grid_name({'meta': dict(c.get('extra') or [])})}")
    ax.set_yscale("log")
    ax.set_xlabel("interfacial stress (MPa, compressive > 0)")
    ax.set_ylabel("probability density (1/MPa)")
    ax.set_title("Challenge item 4 at 250 kPa: stored references with their bands")
    ax.legend()
    fig.tight_layout()
    tmp = f"{out}.tmp{os.getpid()}.png"
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    os.replace(tmp, out)


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ref", default=os.path.join(ROOT, "reference", "challenge"))
    ap.add_argument("--out", default=os.path.join(ROOT, "reports", "readme", "stress_distribution.png"))
    a = ap.parse_args(argv)
    try:
        draw(a.ref, a.out)
    except (OSError, KeyError, ValueError) as e:
        print(f"readme_figure: {e} (the stored stress distributions: scripts/challenge_reference.py)", file=sys.stderr)
        return 2
    print(f"readme_figure: wrote {a.out}")
    return 0
