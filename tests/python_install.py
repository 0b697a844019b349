#!/usr/bin/python3
"""CTest python_install.pip_wheel: the README's install commands, offline, from a clean copy of
the tree (the files git knows, with their working-tree contents; no build directories):

1. a fresh `python3 -m venv --system-site-packages` venv, `pip install --no-build-isolation
   --no-index .`, then, from elsewhere, import, fit and compare fairspline.__version__ with the
   installed metadata and the CMake project version;
2. in the same copy, `python -m build --no-isolation --wheel` (it reuses step 1's CMake tree, so
   the library is compiled once) gives a wheel holding only the package (python/fairspline and
   the extension), which installs into a second fresh venv and passes the same checks;
3. `python -m build --no-isolation --sdist` holds every source the CMake build reads.

Each step is bounded in time and its duration printed. CMAKE_BUILD_PARALLEL_LEVEL (set by
CTest) is how many compilers run at once; CMAKE_ARGS (default -DCMAKE_CXX_FLAGS_RELEASE=-O0,
which keeps make test within its budget) reaches setup.py's CMake configure.

usage: python_install.py SOURCE_DIR WORK_DIR VERSION
"""
import glob
import os
import shutil
import subprocess
import sys
import sysconfig
import tarfile
import time
import zipfile

CHECK = r"""
import importlib.metadata, os, sys
import numpy as np
import fairspline
where = os.path.realpath(fairspline.__file__)
assert where.startswith(os.path.realpath(sys.prefix) + os.sep), (where, sys.prefix)
curve = fairspline.fit(np.array([(1, 90), (3, 105), (6, 120), (10, 100)], float))
assert curve.segments.shape == (3, 4, 2), curve.segments.shape
assert np.allclose(curve.evaluate(curve.knots), curve.points)
print(fairspline.__version__, importlib.metadata.version("fairspline"), where)
"""


def fail(message):
    print(f"python_install: {message}", file=sys.stderr)
    sys.exit(1)


def run(what, command, cwd, timeout, env=None):
    start = time.monotonic()
    step = subprocess.run(command, cwd=cwd, env=env or clean_env(), capture_output=True,
                          text=True, timeout=timeout)
    seconds = time.monotonic() - start
    if step.returncode != 0:
        fail(f"{what} failed ({step.returncode}): {' '.join(command)}\n{step.stdout}\n{step.stderr}")
    print(f"python_install: {what}: {seconds:.1f} s", flush=True)
    return step.stdout


def clean_env():
    # Nothing may reach the build tree's module: no PYTHONPATH, no user site-packages.
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
    env.update(PYTHONNOUSERSITE="1", PIP_NO_INPUT="1", PIP_DISABLE_PIP_VERSION_CHECK="1")
    # The packaging is under test, not the optimizer: the library compiles at -O0 (through
    # setup.py's CMAKE_ARGS, as a user would pass them) in a fraction of -O2's time.
    env.setdefault("CMAKE_ARGS", "-DCMAKE_CXX_FLAGS_RELEASE=-O0")
    return env


def copy_tree(source, target):
    try:
        listing = subprocess.run(
            ["git", "-C", source, "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
            capture_output=True, check=True, timeout=60).stdout.decode().split("\0")
    except (OSError, subprocess.CalledProcessError):  # not a git checkout (a tarball)
        shutil.copytree(source, target, ignore=shutil.ignore_patterns(
            "build*", "out", "dist", ".git", "node_modules", "__pycache__", "*.egg-info"))
        return
    for name in filter(None, listing):
        path = os.path.join(source, name)
        if os.path.isfile(path):  # (a file deleted in the work tree is still listed)
            os.makedirs(os.path.dirname(os.path.join(target, name)), exist_ok=True)
            shutil.copy2(path, os.path.join(target, name))


def make_venv(path):
    run(f"venv {os.path.basename(path)}",
        [sys.executable, "-m", "venv", "--system-site-packages", path], cwd=None, timeout=300)
    return os.path.join(path, "bin", "python")


def check(python, work, version):
    out = run("import and fit", [python, "-c", CHECK], cwd=work, timeout=120).split()
    module_version, metadata_version, where = out[0], out[1], out[2]
    if not module_version == metadata_version == version:
        fail(f"fairspline.__version__ {module_version}, metadata {metadata_version}, CMake "
             f"project {version}: they must agree")
    print(f"python_install: {python} imports fairspline {version} from {where}")


def main():
    source, work, version = sys.argv[1:4]
    shutil.rmtree(work, ignore_errors=True)
    src = os.path.join(work, "src")
    copy_tree(source, src)
    dist = os.path.join(work, "dist")

    python = make_venv(os.path.join(work, "venv-pip"))
    run("pip install --no-build-isolation --no-index .",
        [python, "-m", "pip", "install", "--no-build-isolation", "--no-index", "."],
        cwd=src, timeout=1500)
    check(python, work, version)

    run("python -m build --no-isolation --wheel",
        [python, "-m", "build", "--no-isolation", "--wheel", "--outdir", dist], cwd=src, timeout=600)
    wheels = glob.glob(os.path.join(dist, "*.whl"))
    if len(wheels) != 1:
        fail(f"expected one wheel in {dist}, found {wheels}")
    package = os.path.join(src, "python", "fairspline")
    expected = sorted(["fairspline/_core" + sysconfig.get_config_var("EXT_SUFFIX")] +
                      [f"fairspline/{f}" for f in os.listdir(package) if f != "__pycache__"])
    with zipfile.ZipFile(wheels[0]) as wheel:
        files = sorted(n for n in wheel.namelist() if ".dist-info/" not in n)
    if files != expected:
        fail(f"{os.path.basename(wheels[0])} holds {files}, expected {expected}")
    python = make_venv(os.path.join(work, "venv-wheel"))
    run("pip install --no-index WHEEL",
        [python, "-m", "pip", "install", "--no-index", wheels[0]], cwd=work, timeout=300)
    check(python, work, version)

    run("python -m build --no-isolation --sdist",
        [python, "-m", "build", "--no-isolation", "--sdist", "--outdir", dist], cwd=src, timeout=300)
    needed = {"CMakeLists.txt"}
    for top in ("cmake", "include", "src", "python"):
        for root, dirs, names in os.walk(os.path.join(src, top)):
            dirs[:] = [d for d in dirs if d != "__pycache__"]
            needed.update(os.path.relpath(os.path.join(root, n), src) for n in names)
    (sdist,) = glob.glob(os.path.join(dist, "*.tar.gz"))
    with tarfile.open(sdist) as tar:
        held = {n.split("/", 1)[1] for n in tar.getnames() if "/" in n}
    if needed - held:
        fail(f"{os.path.basename(sdist)} lacks {sorted(needed - held)}")

    shutil.rmtree(work, ignore_errors=True)  # ~100 MB of copies, venvs and objects
    print(f"python_install: pip install ., the wheel and the sdist of fairspline {version}: ok")


if __name__ == "__main__":
    main()
