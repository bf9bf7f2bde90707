"""The compiled part of `pip install .` (pyproject.toml holds the rest): CMake builds the
program `cmc` and the module cmc._core, and the package gets them with the shipped data:

    cmc/_core.*.so          the compiled core
    cmc/bin/cmc             the program, which the console command `cmc` runs
    cmc/share/cmc/          cases/, reference/ and reports/plot_check.py, where the program
                            and the module look for them (solver/cmc/input/DataDir.hpp)

Environment:
    CMAKE_ARGS        more arguments for configuring, e.g. "-DCMC_WISDOM_FROM=FILE"
    CMC_PREBUILT      a build folder already built (cmake --build BUILD): its program and
                      module are packaged as they are and nothing is compiled
    CMC_PIP_BUILD     setuptools' build folder (default build-pip/, beside build/)
Compiling uses CMAKE_BUILD_PARALLEL_LEVEL jobs (default: all cores).
"""
import glob
import os
import re
import shlex
import shutil
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = os.path.dirname(os.path.abspath(__file__))


def project_version():
    """The version of project(cmc VERSION ...) in CMakeLists.txt: one number for both builds."""
    with open(os.path.join(ROOT, "CMakeLists.txt"), encoding="utf-8") as f:
        m = re.search(r"project\(cmc VERSION ([0-9.]+)", f.read())
    if not m:
        sys.exit("setup.py: CMakeLists.txt: expected 'project(cmc VERSION X.Y.Z ...)'")
    return m.group(1)


def run(cmd):
    print("setup.py: " + shlex.join(cmd), flush=True)
    subprocess.run(cmd, check=True)


class CMakeBuild(build_ext):
    """Builds cmc._core (and the program) with CMake instead of setuptools' compiler."""

    def build_extension(self, ext):
        build = os.environ.get("CMC_PREBUILT") or self.cmake_build()
        package = os.path.dirname(os.path.abspath(self.get_ext_fullpath(ext.name)))
        cores = glob.glob(os.path.join(build, "python", "cmc", "_core.*.so"))
        program = os.path.join(build, "cmc")
        if len(cores) != 1 or not os.access(program, os.X_OK):
            sys.exit(f"setup.py: {build}: expected the built program cmc and one python/cmc/_core.*.so "
                     f"(found {len(cores)} module(s)): build it first (cmake --build {build})")
        os.makedirs(os.path.join(package, "bin"), exist_ok=True)
        shutil.copy2(cores[0], self.get_ext_fullpath(ext.name))
        shutil.copy2(program, os.path.join(package, "bin", "cmc"))
        data = os.path.join(package, "share", "cmc")
        for folder in ("cases", "reference"):
            shutil.rmtree(os.path.join(data, folder), ignore_errors=True)
            shutil.copytree(os.path.join(ROOT, folder), os.path.join(data, folder))
        os.makedirs(os.path.join(data, "reports"), exist_ok=True)
        shutil.copy2(os.path.join(ROOT, "reports", "plot_check.py"), os.path.join(data, "reports"))

    def cmake_build(self):
        """Configures and builds the program and the module in build_temp; returns the folder."""
        build = os.path.abspath(os.path.join(self.build_temp, "cmake"))
        configure = ["cmake", "-S", ROOT, "-B", build, "-DCMAKE_BUILD_TYPE=Release", "-DCMC_BUILD_TESTS=OFF",
                     "-DCMC_BUILD_BENCHMARKS=OFF", "-DCMC_PYTHON=ON", f"-DPython_EXECUTABLE={sys.executable}"]
        run(configure + shlex.split(os.environ.get("CMAKE_ARGS", "")))
        run(["cmake", "--build", build, "--target", "cmc_builtin_wisdom"])  # timed plans: alone first
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL") or str(os.cpu_count() or 2)
        run(["cmake", "--build", build, "-j", jobs, "--target", "cmc", "cmc_python"])
        return build


BUILD_BASE = os.environ.get("CMC_PIP_BUILD") or os.path.join(ROOT, "build-pip")
os.makedirs(BUILD_BASE, exist_ok=True)
setup(
    version=project_version(),
    ext_modules=[Extension("cmc._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    # setuptools' folders (build/ is CMake's): the build and the package's metadata
    options={"build": {"build_base": BUILD_BASE}, "egg_info": {"egg_base": BUILD_BASE}},
)
