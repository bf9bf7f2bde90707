"""Shared pieces of the Python module's tests (ctest runs each file with PYTHONPATH set to
BUILD/python, CMC_EXE to the cmc program and CMC_SOURCE to the source tree:
python/python.cmake)."""
import os
import subprocess
import sys

import pytest

SOURCE = os.environ.get("CMC_SOURCE") or os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
CMC_EXE = os.environ.get("CMC_EXE") or os.path.join(SOURCE, "build", "cmc")


def case_path(relative):
    return os.path.join(SOURCE, "cases", relative)


def cmc_cli(*args, cwd=None):
    """Run the cmc program; returns the CompletedProcess (text output)."""
    return subprocess.run([CMC_EXE, *args], capture_output=True, text=True, cwd=cwd)


def python(code, env_extra=None, timeout=120):
    """Run `code` in a fresh /usr/bin/python3 with this process's path; returns the CompletedProcess."""
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p))
    env.update(env_extra or {})
    return subprocess.run(["/usr/bin/python3", "-c", code], capture_output=True, text=True, env=env, timeout=timeout)


@pytest.fixture
def cmc():
    import cmc as module
    return module
