"""The console command `cmc` that `pip install` makes: the program built with the package
(cmc/bin/cmc, setup.py), run with the same arguments. Where the package was not installed
by pip (the build tree's copy, PYTHONPATH=build/python) there is none: run build/cmc."""
import os
import sys


def main() -> int:
    program = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bin", "cmc")
    if not os.access(program, os.X_OK):
        print(f"cmc: {program} not found: this copy of the package has no program "
              "(install it with pip, or run the build's own: build/cmc)", file=sys.stderr)
        return 2
    os.execv(program, ["cmc"] + sys.argv[1:])
    return 2  # not reached: execv replaces this process


if __name__ == "__main__":
    sys.exit(main())
