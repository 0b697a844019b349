#!/usr/bin/python3
"""CTest consumer.install_web: `cmake --install` of the build into a scratch prefix puts the web
editor's files in <prefix>/share/fairspline/web (FAIRSPLINE_WEB_INSTALL_DIR) and the command in
<prefix>/bin, and the installed `fairspline serve` finds those files by itself: `serve --help`
names them as the default --root, and a server started on a free loopback port answers GET /
with the installed index.html. With the Python module built, the same install puts the
package in <prefix>/PYTHON_INSTALL_DIR/fairspline (FAIRSPLINE_PYTHON_INSTALL_DIR), and
/usr/bin/python3 with that directory on its path imports it from there and fits. Every step is
bounded in time.

usage: consumer_install_web.py CMAKE BUILD_DIR WORK_DIR CONFIG WEB_SOURCE_DIR WEB_INSTALL_DIR
                               [PYTHON_INSTALL_DIR]
"""
import filecmp
import os
import shutil
import subprocess
import sys
import threading
import urllib.request


def fail(message):
    print(f"consumer.install_web: {message}", file=sys.stderr)
    sys.exit(1)


CHECK = """
import os, sys, fairspline
assert os.path.realpath(fairspline.__file__).startswith(sys.argv[1]), fairspline.__file__
curve = fairspline.fit([(1, 90), (3, 105), (6, 120), (10, 100)])
print(fairspline.__version__, len(curve.segments))
"""


def check_python_package(prefix, python_install_dir):
    site = os.path.realpath(os.path.join(prefix, python_install_dir))
    package = os.path.join(site, "fairspline")
    if not os.path.isfile(os.path.join(package, "__init__.py")):
        fail(f"cmake --install put no Python package in {package}")
    env = {k: v for k, v in os.environ.items() if not k.startswith("PYTHON")}
    env["PYTHONPATH"] = site
    step = subprocess.run(["/usr/bin/python3", "-c", CHECK, package], capture_output=True,
                          text=True, timeout=60, env=env, cwd=prefix)
    if step.returncode != 0 or step.stdout.split()[1:] != ["3"]:
        fail(f"the installed package {package} does not import and fit:\n{step.stdout}\n"
             f"{step.stderr}")
    print(f"consumer.install_web: {package} imports, version {step.stdout.split()[0]}")


def main():
    cmake, build_dir, work_dir, config, web_source, web_install_dir = sys.argv[1:7]
    python_install_dir = sys.argv[7] if len(sys.argv) > 7 else ""
    prefix = os.path.join(work_dir, "prefix")
    shutil.rmtree(prefix, ignore_errors=True)
    install = [cmake, "--install", build_dir, "--prefix", prefix]
    if config:
        install += ["--config", config]
    step = subprocess.run(install, capture_output=True, text=True, timeout=120)
    if step.returncode != 0:
        fail(f"cmake --install failed ({step.returncode}):\n{step.stdout}\n{step.stderr}")

    web_root = os.path.realpath(os.path.join(prefix, web_install_dir))
    sources = sorted(f for f in os.listdir(web_source)
                     if os.path.isfile(os.path.join(web_source, f)))
    installed = sorted(os.listdir(web_root)) if os.path.isdir(web_root) else []
    if installed != sources:
        fail(f"{web_root} holds {installed}, expected the files of {web_source}: {sources}")
    _, mismatch, errors = filecmp.cmpfiles(web_source, web_root, sources, shallow=False)
    if mismatch or errors:
        fail(f"installed web files differ from the sources: {mismatch + errors}")

    if python_install_dir:
        check_python_package(prefix, python_install_dir)

    exe = os.path.join(prefix, "bin", "fairspline")
    if not os.access(exe, os.X_OK):
        fail(f"no executable {exe}")
    step = subprocess.run([exe, "serve", "--help"], capture_output=True, text=True, timeout=30)
    if step.returncode != 0 or f"(default: {web_root})" not in " ".join(step.stdout.split()):
        fail(f"`fairspline serve --help` does not name {web_root} as the default --root:\n"
             f"{step.stdout}\n{step.stderr}")

    server = subprocess.Popen([exe, "serve", "--host", "127.0.0.1", "--port", "0"],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        first = []
        reader = threading.Thread(target=lambda: first.append(server.stdout.readline()),
                                  daemon=True)
        reader.start()
        reader.join(timeout=30)
        line = first[0].strip() if first else ""
        prefix_text = "fairspline: serving http://127.0.0.1:"
        if not line.startswith(prefix_text):
            fail(f"the installed server did not start: '{line}'")
        port = int(line[len(prefix_text):].rstrip("/"))
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=30) as response:
            status, body = response.status, response.read()
        with open(os.path.join(web_root, "index.html"), "rb") as f:
            expected = f.read()
        if status != 200 or body != expected:
            fail(f"GET / gave HTTP {status} and {len(body)} bytes, not the installed index.html")
    finally:
        server.terminate()
        try:
            server.wait(timeout=10)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait(timeout=10)
    print(f"consumer.install_web: {exe} serves {web_root} ({len(sources)} files) on port {port}")


if __name__ == "__main__":
    main()
