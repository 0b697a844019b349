"""Build of the Python package `fairspline` for pip and `python3 -m build` (pyproject.toml).

CMake builds the library and the extension (target fairspline_python) for the interpreter that
runs this file, in Release, in a build tree of its own under build-python/; nothing else of the
project (tests, CLI, benchmarks) is configured. The package is then what `cmake --install
--component python` lays out (python/CMakeLists.txt), so pip, wheels and CMake installs hold the
same files. Environment: CMAKE_BUILD_PARALLEL_LEVEL (default: all cores), CMAKE_GENERATOR, and
CMAKE_ARGS (extra configure arguments, e.g. -DCMAKE_CXX_COMPILER=clang++).
"""

import hashlib
import os
import re
import shlex
import shutil
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


def cmake_project_version():
    # One source of truth: the version of project(fairspline VERSION ...), which the extension
    # also reports (fairspline.__version__).
    text = (ROOT / "CMakeLists.txt").read_text(encoding="utf-8")
    match = re.search(r"^project\(\s*fairspline\s+VERSION\s+([0-9][0-9.]*)", text, re.MULTILINE)
    if not match:
        raise RuntimeError("no project(fairspline VERSION ...) line in CMakeLists.txt")
    return match.group(1)


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        cmake = shutil.which("cmake")
        if cmake is None:
            raise RuntimeError("building fairspline needs cmake >= 3.20 (Debian: apt install cmake)")
        # One CMake tree per interpreter: a tree configured for another Python keeps that one's
        # headers and ABI in its cache.
        key = hashlib.sha1(sys.executable.encode()).hexdigest()[:10]
        build_dir = Path(self.build_temp).resolve() / f"cmake-{key}"
        # The directory that holds the package fairspline/ (build_lib, or the source tree for
        # --inplace): the component is installed there.
        package_root = Path(self.get_ext_fullpath(ext.name)).resolve().parent.parent
        configure = [
            cmake, "-S", str(ROOT), "-B", str(build_dir),
            "-DCMAKE_BUILD_TYPE=Release",
            f"-DPython_EXECUTABLE={sys.executable}",
            "-DFAIRSPLINE_BUILD_PYTHON=ON",
            "-DFAIRSPLINE_BUILD_CLI=OFF",
            "-DFAIRSPLINE_BUILD_TESTS=OFF",
            "-DFAIRSPLINE_BUILD_BENCH=OFF",
            "-DFAIRSPLINE_BUILD_TOOLS=OFF",
            "-DBUILD_SHARED_LIBS=OFF",  # the extension carries the library: nothing else to ship
            "-DFAIRSPLINE_PYTHON_INSTALL_DIR=.",
        ]
        try:  # pybind11 from pip, or Debian's python3-pybind11 (else CMake finds pybind11-dev)
            import pybind11

            configure.append(f"-Dpybind11_DIR={pybind11.get_cmake_dir()}")
        except ImportError:
            pass
        configure += shlex.split(os.environ.get("CMAKE_ARGS", ""))
        build = [cmake, "--build", str(build_dir), "--target", "fairspline_python"]
        if "CMAKE_BUILD_PARALLEL_LEVEL" not in os.environ:
            build += ["--parallel", str(self.parallel or os.cpu_count() or 1)]
        install = [cmake, "--install", str(build_dir), "--component", "python",
                   "--prefix", str(package_root)]
        for command in (configure, build, install):
            print(" ".join(shlex.quote(c) for c in command), flush=True)
            subprocess.run(command, check=True)
        built = Path(self.get_ext_fullpath(ext.name))
        if not built.exists():
            found = sorted(p.name for p in built.parent.glob("_core*"))
            raise RuntimeError(f"CMake installed {found}, not {built.name} (another interpreter?)")


# Older setuptools (58, Python 3.9's venv) refuse an egg_base that does not exist yet.
os.makedirs(ROOT / "build-python", exist_ok=True)

setup(
    version=cmake_project_version(),
    # Setuptools' own files stay out of the source tree's build/ (the CMake build of `make`).
    options={"build": {"build_base": "build-python"}, "egg_info": {"egg_base": "build-python"}},
    packages=[],  # the package's files come from the CMake install above
    ext_modules=[Extension("fairspline._core", sources=[])],
    cmdclass={"build_ext": CMakeBuild},
    zip_safe=False,
)
