"""Docstrings come from the C++ headers' doc comments (one source, extracted at build time)."""

import importlib.util
import re

import fairspline
from conftest import INCLUDE_DIR, SOURCE_DIR

# The generator's own translation of C++ names, loaded from its file: putting python/ on
# sys.path would let processes spawned later (Dask's workers) import the source package, which
# has no compiled _core.
_spec = importlib.util.spec_from_file_location("gen_docstrings",
                                               SOURCE_DIR / "python" / "gen_docstrings.py")
gen_docstrings = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(gen_docstrings)

CONSTANTS = gen_docstrings.header_constants(str(SOURCE_DIR / "include"))


def header_doc(header, declaration):
    """The `///` lines directly above the line that starts with `declaration` in a header."""
    lines = (INCLUDE_DIR / header).read_text(encoding="utf-8").splitlines()
    (i,) = [k for k, line in enumerate(lines) if line.strip().startswith(declaration)]
    doc = []
    while i > 0 and lines[i - 1].strip().startswith("///"):
        i -= 1
        doc.insert(0, lines[i].strip()[3:].strip())
    assert doc, "no doc comment above {} in {}".format(declaration, header)
    return [gen_docstrings.pythonize(line, CONSTANTS) for line in doc]


def assert_in(doc_lines, text):
    for line in doc_lines:
        assert line in text, "{!r} is not in the docstring:\n{}".format(line, text)


def test_functions_carry_their_header_comments():
    assert_in(header_doc("registry.hpp", "FitResult fit("), fairspline.fit.__doc__)
    assert_in(header_doc("batch.hpp", "std::vector<BatchOutcome> fit_many("),
              fairspline.fit_many.__doc__)
    assert_in(header_doc("registry.hpp", "const std::vector<MethodInfo>& methods();"),
              fairspline.methods.__doc__)
    assert_in(header_doc("fit.hpp", "double alpha = kDefaultAlpha;"), fairspline.fit.__doc__)
    assert_in(header_doc("fit.hpp", "std::optional<Vec2> start_tangent;"),
              fairspline.fit.__doc__)
    # The header's own sentence, verbatim.
    assert "validates options, runs the method, checks that no" in fairspline.fit.__doc__


def test_curve_methods_carry_the_spline_comments():
    pairs = [("Point eval(double t) const;", fairspline.Curve.evaluate),
             ("Vec2 derivative(double t, int order = 1) const;", fairspline.Curve.derivative),
             ("double curvature(double t) const;", fairspline.Curve.curvature),
             ("std::vector<Point> sample(std::size_t count) const;", fairspline.Curve.sample)]
    for declaration, fn in pairs:
        assert_in(header_doc("spline.hpp", declaration), fn.__doc__)
    assert_in(header_doc("io/json.hpp", "nlohmann::json to_json(const FitResult& result);"),
              fairspline.Curve.to_json.__doc__)
    assert_in(header_doc("io/svg.hpp", "std::string write_svg("), fairspline.Curve.to_svg.__doc__)
    assert_in(header_doc("fit.hpp", "struct FitResult"), fairspline.Curve.__doc__)
    assert "outside" in fairspline.Curve.evaluate.__doc__  # the documented range policy


def test_error_lists_every_code_with_its_comment():
    doc = fairspline.Error.__doc__
    assert_in(header_doc("error.hpp", "class Error"), doc)
    names = re.findall(r'return "([a-z_]+)";', (SOURCE_DIR / "src" / "error.cpp").read_text())
    assert len(names) >= 14
    for name in names:
        if name != "unknown":
            assert re.search(r"^\s+{}\s+\S".format(name), doc, re.M), name
    assert "two consecutive points coincide" in doc  # kRepeatedPoint's ///< comment


def test_python_only_functions_have_docstrings():
    assert "Matplotlib" in fairspline.plot.__doc__
    assert fairspline.__doc__ and "fit_many" in fairspline.__doc__


def public_docstrings():
    """(name, docstring) of every public function, class, method and property of the module."""
    out = []
    for name in fairspline.__all__:
        obj = getattr(fairspline, name)
        if callable(obj) and getattr(obj, "__doc__", None):
            out.append((name, obj.__doc__))
        if isinstance(obj, type) and obj.__module__.startswith("fairspline"):
            for attr, member in vars(obj).items():
                doc = getattr(member, "__doc__", None)
                if doc and (not attr.startswith("_") or attr in ("__call__", "__init__")):
                    out.append((name + "." + attr, doc))
    return out


def test_docstrings_speak_python_not_cpp():
    # gen_docstrings.pythonize turns the headers' C++ names into the Python ones.
    cpp = re.compile(r"::|\bk[A-Z][a-zA-Z]+\b|\bnullopt\b|\bThrows\b|std::")
    found = [(name, m.group(0)) for name, doc in public_docstrings()
             for m in [cpp.search(doc.split("\n", 1)[-1])] if m]
    assert not found, found
    assert len(public_docstrings()) > 60


def test_numpy_style_sections_and_their_examples_run():
    import doctest

    for fn in (fairspline.fit, fairspline.fit_many):
        for section in ("Parameters\n----------", "Returns\n-------", "Raises\n------",
                        "Examples\n--------"):
            assert section in fn.__doc__, (fn.__name__, section)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    tries = 0
    for name, doc in public_docstrings():
        test = doctest.DocTestParser().get_doctest(doc, {}, name, None, 0)
        runner.run(test)
        tries += len(test.examples)
    assert runner.failures == 0
    assert tries >= 15
