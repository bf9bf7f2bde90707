#!/usr/bin/python3
"""cmc installed as a user installs it, then used from outside the checkout (ctest label
'install'; docs/install.md, "Installing").

usage: tests/install/install_test.py TEST SOURCE BUILD WORK

TEST is one of
  prefix        `cmake --install BUILD --prefix P`, then P moved elsewhere (an install is one
                tree that may move): P/bin/cmc runs the installed Hertz case named as
                cases/validation/hertz-free.toml from a folder of its own (found under
                P/share/cmc, which a missing case's message names), `cmc check --list` finds
                the stored references, the installed Python package loads the same case, and
                a ten-line consumer project (tests/install/consumer) built with
                find_package(cmc) and cmc::cmc solves the Hertz case through the library
                within the case's 1e-3 of Hertz's penetration.
  pip_target    `pip install --no-build-isolation --target T SOURCE`, then from a folder
                outside the checkout with PYTHONPATH=T alone: `import cmc` is T's, the
                installed Hertz case loads by its relative name and solves within 1e-3 of
                Hertz, and the console command T/bin/cmc answers --help.
  pip_venv      a venv made with --system-site-packages (Debian's pip installs into no
                other), `pip install --no-build-isolation SOURCE` into it, then from / with
                no PYTHONPATH: `python -c "import cmc; print(cmc.solve)"` and `cmc --help`.
  pip_fresh     as pip_target, with the C++ core compiled by pip itself (setup.py driving
                CMake in a folder of its own; label slow: a full build). The FFT plans are
                BUILD's, so that nothing is timed beside the compile.
Each but pip_fresh packages BUILD's program and module as built (CMC_PREBUILT, setup.py):
what is tested is what the install puts where, not the compiler a second time. WORK is
emptied first; nothing is written into SOURCE.
"""
import glob
import os
import shutil
import subprocess
import sys

HERTZ = "cases/validation/hertz-free.toml"  # relative: only an installed data folder holds it here
# Hertz's penetration at the case's three forces on 64²: within the case's own 1e-3 (6.8e-4
# measured there, cases/validation/hertz-free.toml).
SOLVE = f"""
import cmc, sys
c = cmc.Case.load({HERTZ!r}, set={{"grid.n": 64}})
assert c.file.startswith(sys.argv[1]), (c.file, sys.argv[1])
r = cmc.run(c)
for s in r.summary["steps"]:
    exact = cmc.analytic.hertz(1e6, 1e-2, force=s["force"]).penetration
    err = abs(s["penetration"] / exact - 1)
    print(f"force {{s['force']:.4g}} N: penetration {{s['penetration']:.6g}} m, Hertz {{exact:.6g}} m, error {{err:.2e}}")
    assert err < 1e-3, err
print("cmc from", cmc.__file__)
"""
failures = []


def run(cmd, cwd=None, env=None, expect=0):
    """Runs cmd; records a failure (with its output) unless it exits `expect`. Its output."""
    try:
        r = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True)
    except OSError as e:
        failures.append(f"{cmd[0]}: {e}")
        return ""
    shown = " ".join(a if len(a) < 80 else a.strip().split("\n")[0] + " ..." for a in cmd)
    if r.returncode != expect:
        failures.append(f"{shown} (in {cwd or os.getcwd()}) exited {r.returncode}, expected {expect}:\n"
                        f"{r.stdout[-3000:]}{r.stderr[-3000:]}")
    else:
        print(f"ok   {shown}")
    return r.stdout + r.stderr


def clean_env(**extra):
    """The environment without the build's PYTHONPATH (ctest sets it) and any data folder."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "CMC_DATA_DIR", "CMC_REFERENCE_DIR")}
    env.update(extra)
    return env


def expect(cond, what):
    print(f"{'ok  ' if cond else 'FAIL'} {what}")
    if not cond:
        failures.append(what)


def installed_python_dir(prefix):
    found = glob.glob(os.path.join(prefix, "lib", "python3*", "*-packages", "cmc", "__init__.py"))
    return os.path.dirname(os.path.dirname(found[0])) if found else None


def test_prefix(source, build, work):
    first, prefix = os.path.join(work, "first"), os.path.join(work, "moved")
    run(["cmake", "--install", build, "--prefix", first])
    os.rename(first, prefix)
    for f in ("bin/cmc", "lib/cmake/cmc/cmcConfig.cmake", "include/cmc/input/Case.hpp",
              "include/cmc/validation/Check.hpp", "share/cmc/" + HERTZ, "share/cmc/reference/challenge/README.md",
              "share/cmc/reports/plot_check.py"):
        expect(os.path.exists(os.path.join(prefix, f)), f"installed {f}")
    expect(bool(glob.glob(os.path.join(prefix, "lib*", "**", "libcmc.a"), recursive=True)), "installed libcmc.a")
    elsewhere = os.path.join(work, "elsewhere")
    os.makedirs(elsewhere)
    cmc = os.path.join(prefix, "bin", "cmc")
    run([cmc, "run", HERTZ, "--set", "grid.n=32", "--out", "hertz", "--quiet"], cwd=elsewhere, env=clean_env())
    expect(os.path.exists(os.path.join(elsewhere, "hertz", "summary.json")), "the installed case ran from elsewhere")
    said = run([cmc, "run", "no-such-case.toml", "--out", "none"], cwd=elsewhere, env=clean_env(), expect=2)
    expect(os.path.join(prefix, "share", "cmc", "no-such-case.toml") in said,
           f"a missing case's message names the moved prefix's data folder: {said.strip()}")
    listed = run([cmc, "check", "--list"], cwd=elsewhere, env=clean_env())
    expect("stored reference: with adhesion yes" in listed, "cmc check --list finds the installed references")
    pydir = installed_python_dir(prefix)
    expect(pydir is not None, f"the Python package under {prefix}/lib/python3*/")
    if pydir:
        run([sys.executable, "-c", SOLVE, os.path.join(prefix, "share", "cmc")], cwd=elsewhere,
            env=clean_env(PYTHONPATH=pydir))
    consumer = os.path.join(work, "consumer")
    run(["cmake", "-S", os.path.join(source, "tests", "install", "consumer"), "-B", consumer,
         f"-DCMAKE_PREFIX_PATH={prefix}", "-DCMAKE_BUILD_TYPE=Release"])
    run(["cmake", "--build", consumer])
    print(run([os.path.join(consumer, "hertz")], cwd=elsewhere, env=clean_env()))


def pip_install(source, build, work, args, python=sys.executable, prebuilt=True):
    env = clean_env(CMC_PIP_BUILD=os.path.join(work, "pip-build"))
    if prebuilt:
        env["CMC_PREBUILT"] = build
    else:
        env["CMAKE_ARGS"] = f"-DCMC_WISDOM_FROM={os.path.join(build, 'generated', 'fftw_wisdom.cpp')}"
    run([python, "-m", "pip", "install", "--no-build-isolation", "--no-deps", "--no-index", "--quiet",
         *args, source], cwd=work, env=env)


def test_pip_target(source, build, work, prebuilt=True):
    target = os.path.join(work, "target")
    pip_install(source, build, work, ["--target", target], prebuilt=prebuilt)
    elsewhere = os.path.join(work, "elsewhere")
    os.makedirs(elsewhere)
    said = run([sys.executable, "-c", SOLVE, os.path.join(target, "cmc", "share", "cmc")], cwd=elsewhere,
               env=clean_env(PYTHONPATH=target))
    print(said)
    expect(f"cmc from {target}" in said, "import cmc found the installed package")
    helped = run([os.path.join(target, "bin", "cmc"), "--help"], cwd=elsewhere, env=clean_env(PYTHONPATH=target))
    expect("usage" in helped.lower() and "run" in helped, "the console command's --help")


def test_pip_venv(source, build, work):
    venv = os.path.join(work, "venv")
    run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", venv])
    python = os.path.join(venv, "bin", "python")
    pip_install(source, build, work, [], python=python)
    said = run([python, "-c", "import cmc; print(cmc.solve); print(cmc.__file__)"], cwd="/", env=clean_env())
    expect("function solve" in said and venv in said, f"import cmc from / in the venv: {said.strip()}")
    helped = run([os.path.join(venv, "bin", "cmc"), "--help"], cwd="/", env=clean_env())
    expect("usage" in helped.lower() and "run" in helped, "the console command's --help")


def main(argv):
    tests = {"prefix": test_prefix, "pip_target": test_pip_target, "pip_venv": test_pip_venv,
             "pip_fresh": lambda s, b, w: test_pip_target(s, b, w, prebuilt=False)}
    if len(argv) != 5 or argv[1] not in tests:
        print(__doc__, file=sys.stderr)
        return 2
    source, build, work = (os.path.abspath(a) for a in argv[2:])
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    tests[argv[1]](source, build, work)
    for f in failures:
        print("FAIL " + f, file=sys.stderr)
    print(f"install_test {argv[1]}: {'FAILED' if failures else 'ok'}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
