"""Docstrings come from the C++ headers' doc comments (one source, extracted at build time)."""

import re

import fairspline
from conftest import INCLUDE_DIR, SOURCE_DIR


def header_doc(header, declaration):
    """The `///` lines directly above the line that starts with `declaration` in a header."""
    lines = (INCLUDE_DIR / header).read_text(encoding="utf-8").splitlines()
    (i,) = [k for k, line in enumerate(lines) if line.strip().startswith(declaration)]
    doc = []
    while i > 0 and lines[i - 1].strip().startswith("///"):
        i -= 1
        doc.insert(0, lines[i].strip()[3:].strip())
    assert doc, "no doc comment above {} in {}".format(declaration, header)
    return doc


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
