"""The type stubs (fairspline/__init__.pyi, py.typed) agree with the module: mypy's stubtest,
every parameter's name, kind and default against pybind11's signatures, the method names, and
a type check of user code that must pass and code that must fail."""

import ast
import inspect
import os
import pathlib
import re
import subprocess
import sys

import pytest

import fairspline
from fairspline import _core

PACKAGE = pathlib.Path(fairspline.__file__).resolve().parent
STUB = PACKAGE / "__init__.pyi"
ALLOWLIST = pathlib.Path(__file__).resolve().parents[2] / "python" / "stubtest-allowlist.txt"


def stub_tree():
    return ast.parse(STUB.read_text(encoding="utf-8"))


def stub_functions():
    """{qualified name: ast.FunctionDef} of the stub; _Geometry's methods under Curve and Path."""
    out = {}
    for node in stub_tree().body:
        if isinstance(node, ast.FunctionDef):
            out[node.name] = node
        elif isinstance(node, ast.ClassDef):
            owners = ["Curve", "Path"] if node.name == "_Geometry" else [node.name]
            for item in node.body:
                properties = [d for d in getattr(item, "decorator_list", [])
                              if isinstance(d, ast.Name) and d.id == "property"]
                if isinstance(item, ast.FunctionDef) and not properties:
                    for owner in owners:
                        # An @overload's last variant stands for them all (same parameters).
                        out[f"{owner}.{item.name}"] = item
    return out


def stub_parameters(fn):
    """[(name, kind, default text or None)] without self, as the stub declares them."""
    a = fn.args
    params = []
    positional = a.posonlyargs + a.args
    defaults = [None] * (len(positional) - len(a.defaults)) + [ast.unparse(d) for d in a.defaults]
    for arg, default in zip(positional, defaults):
        params.append((arg.arg, "positional", default))
    for arg, default in zip(a.kwonlyargs, a.kw_defaults):
        params.append((arg.arg, "keyword", ast.unparse(default) if default else None))
    if a.kwarg:
        params.append((a.kwarg.arg, "kwargs", None))
    return [p for p in params if p[0] != "self"]


def runtime_parameters(fn):
    """The same from pybind11's signature line (builtins have no inspect.signature), or from
    inspect for pure-Python functions."""
    try:
        sig = inspect.signature(fn)
    except (TypeError, ValueError):
        sig = None
    if sig is not None and not fn.__doc__.lstrip().startswith(fn.__name__ + "("):
        out = []
        for p in sig.parameters.values():
            if p.name == "self":
                continue
            kind = {p.KEYWORD_ONLY: "keyword", p.VAR_KEYWORD: "kwargs"}.get(p.kind, "positional")
            out.append((p.name, kind, None if p.default is p.empty else repr(p.default)))
        return out
    first = fn.__doc__.lstrip().split("\n", 1)[0]
    inner = first[first.index("(") + 1:first.rindex(") ->")]
    parts, depth, cur = [], 0, ""
    for ch in inner:
        depth += ch in "[(" and 1 or (ch in "])" and -1 or 0)
        if ch == "," and depth == 0:
            parts.append(cur.strip())
            cur = ""
        else:
            cur += ch
    if cur.strip():
        parts.append(cur.strip())
    out, kind = [], "positional"
    for part in parts:
        if part == "*":
            kind = "keyword"
            continue
        if part.startswith("**"):
            out.append((part[2:], "kwargs", None))
            continue
        name = re.match(r"\w+", part).group(0)
        default = part.split(" = ", 1)[1] if " = " in part else None
        if name != "self":
            out.append((name, kind, default))
    return out


def same_default(stub, runtime):
    if stub is None or runtime is None:
        return stub == runtime
    return ast.literal_eval(stub) == ast.literal_eval(runtime)


def test_every_parameter_agrees_with_the_module():
    checked = 0
    for name, node in stub_functions().items():
        owner, _, attr = name.rpartition(".")
        target = getattr(getattr(fairspline, owner) if owner else fairspline, attr)
        if attr in ("__init__", "__eq__") and owner == "Curve" or attr == "__eq__":
            continue  # pybind11's generated ones: (self, other) / not constructible
        stub = stub_parameters(node)
        try:
            runtime = runtime_parameters(target)
        except ValueError as e:
            raise AssertionError(f"{name}: no signature in {target.__doc__[:80]!r}") from e
        if attr == "to_svg":  # **kwargs under another name
            runtime = [(n if k != "kwargs" else "options", k, d) for n, k, d in runtime]
        assert [(n, k) for n, k, _ in stub] == [(n, k) for n, k, _ in runtime], name
        for (n, _, sd), (_, _, rd) in zip(stub, runtime):
            assert same_default(sd, rd), f"{name}({n}): stub default {sd}, module {rd}"
        checked += 1
    assert checked >= 45


def test_method_names_and_report_levels_are_the_modules():
    literal = next(n for n in stub_tree().body
                   if isinstance(n, ast.Assign) and n.targets[0].id == "MethodName")
    names = {e.value for e in literal.value.slice.elts}
    assert names == {m["name"] for m in fairspline.methods()}
    assert set(fairspline.MethodName.__args__) == {fairspline._Literal[n] for n in names}
    assert "'basic'" in _core.fit.__doc__.split("\n", 1)[0]  # the default the stub states


def test_py_typed_ships_beside_the_stub():
    assert (PACKAGE / "py.typed").is_file() and STUB.is_file()


mypy = pytest.importorskip("mypy", reason="python3-mypy (scripts/install-deps)")


def run_mypy(args, tmp_path):
    config = tmp_path / "mypy.ini"
    # matplotlib ships no types in Debian 12; the stub's own imports (numpy) do.
    config.write_text("[mypy]\nignore_missing_imports = True\n")
    env = dict(os.environ, MYPYPATH=str(PACKAGE.parent), PYTHONPATH=str(PACKAGE.parent))
    flag = "--mypy-config-file" if args[0] == "mypy.stubtest" else "--config-file"
    return subprocess.run([sys.executable, "-m", *args, flag, str(config)],
                          capture_output=True, text=True, env=env, cwd=tmp_path, timeout=300)


def test_stubtest_finds_no_difference(tmp_path):
    step = run_mypy(["mypy.stubtest", "fairspline", "--allowlist", str(ALLOWLIST)], tmp_path)
    assert step.returncode == 0, step.stdout + step.stderr


def test_user_code_type_checks_and_mistakes_do_not(tmp_path):
    good = tmp_path / "good.py"
    good.write_text(
        "import numpy as np\nimport fairspline\n"
        "c: fairspline.Curve = fairspline.fit(np.zeros((3, 2)), 'cond-g2', report='basic')\n"
        "n: float = c.length()\n"
        "box: tuple[float, float, float, float] = c.bounds()\n"
        "p: fairspline.Path = c.reversed().transformed([1, 0, 0, 1, 0, 0])\n"
        "pts, t = p.flatten(0.1)\n"
        "d: str = c.svg_path()\n")
    step = run_mypy(["mypy", "--strict", str(good)], tmp_path)
    assert step.returncode == 0, step.stdout + step.stderr
    bad = tmp_path / "bad.py"
    bad.write_text("import fairspline\n"
                   "fairspline.fit([(0, 0), (1, 1)], report='ful')\n"
                   "s: str = fairspline.fit([(0, 0), (1, 1)]).length()\n")
    step = run_mypy(["mypy", str(bad)], tmp_path)
    assert step.returncode == 1
    assert 'report' in step.stdout and 'incompatible type "str"' in step.stdout.lower() or \
        "ful" in step.stdout, step.stdout
    assert step.stdout.count("error:") == 2, step.stdout
