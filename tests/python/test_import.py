"""The package without and with its compiled core: cmc.analysis imports without it, the
core's names say how to build it, and importing the whole API takes well under a second of CPU time."""
import json

from conftest import SOURCE, python


def test_the_pure_python_package_imports_without_the_core():
    code = """
import cmc, cmc.analysis
try:
    cmc.solve
except ImportError as e:
    print(e)
"""
    r = python(code, env_extra={"PYTHONPATH": SOURCE + "/python"})
    assert r.returncode == 0, r.stderr
    assert "cmc._core" in r.stdout and "scripts/setup.sh" in r.stdout and "PYTHONPATH=build/python" in r.stdout


def test_import_cmc_loads_nothing_compiled():
    r = python("import json, sys, cmc\n"
               "print(json.dumps(sorted(m for m in sys.modules if m.startswith(('cmc', 'numpy')))))")
    assert r.returncode == 0, r.stderr
    assert json.loads(r.stdout) == ["cmc"]


def test_the_whole_api_imports_in_under_a_second():
    code = """
import time
t = time.process_time()
import cmc
cmc.Case, cmc.run, cmc.solve, cmc.self_affine, cmc.check, cmc.analytic.hertz
print(time.process_time() - t)
"""
    # CPU time, not wall time: on a machine busy with other runs the wall time of the same import
    # grew past 1 s (load average 8 on 2 cores) while its CPU time did not.
    seconds = []
    for _ in range(3):  # the best of three
        r = python(code)
        assert r.returncode == 0, r.stderr
        seconds.append(float(r.stdout))
    assert min(seconds) < 1.0, seconds


def test_every_public_name_has_a_docstring(cmc):
    for name in cmc.__all__:
        obj = getattr(cmc, name)
        assert (obj.__doc__ or "").strip(), name
    for name in ("hertz", "hertz_pressure", "hertz_periodic_penetration"):
        assert getattr(cmc.analytic, name).__doc__, name
