"""The challenge's case files as the scripts that run them read them (cases/challenge/)."""
import os


def tabor_values(root: str) -> list[str]:
    """The Tabor sweep's mu_T as written in cases/challenge/tabor-values of the repository at
    root (as text: scripts/gpu/check.sh matches the words)."""
    with open(os.path.join(root, "cases", "challenge", "tabor-values")) as f:
        return [v for line in f if not line.startswith("#") for v in line.split()]
