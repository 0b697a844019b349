#!/usr/bin/python3
"""Extracts the doc comments of chosen C++ declarations into a header for the Python module.

The public headers' `///` comments are the single source of the Python docstrings: this script
(run by CMake whenever one of the headers changes) copies them into
`fairspline_py::doc::<key>` string constants that python/module.cpp composes into docstrings.

Usage: gen_docstrings.py INCLUDE_DIR OUTPUT_HEADER

Each entry of SYMBOLS names a header and a regular expression that must match exactly one line
of it (the declaration); a missing or ambiguous declaration is an error, so a renamed symbol
breaks the build instead of silently losing its docstring. Kinds:
  decl  the `///` lines directly above the declaration, plus a trailing `///<` comment on it
  file  the leading `//` comment block of the header (its overview)
  enum  every enumerator of the enum opened on the matched line, one line each:
        "  snake_case_name  its ///< comment" (kRepeatedPoint -> repeated_point)
"""

import os
import re
import sys

SYMBOLS = [
    # key, kind, header (relative to include/fairspline), declaration regex
    ("fit", "decl", "registry.hpp", r"^FitResult fit\("),
    ("methods", "decl", "registry.hpp", r"^const std::vector<MethodInfo>& methods\(\);"),
    ("method_schema", "decl", "registry.hpp", r"^nlohmann::json method_schema\("),
    ("default_method_name", "decl", "registry.hpp", r"^std::string_view default_method_name\("),
    ("resolve_options", "decl", "registry.hpp", r"^nlohmann::json resolve_options\("),
    ("batch_overview", "file", "batch.hpp", None),
    ("fit_many", "decl", "batch.hpp", r"^std::vector<BatchOutcome> fit_many\("),
    ("batch_threads", "decl", "batch.hpp", r"^\s*unsigned threads = 0;"),
    ("error", "decl", "error.hpp", r"^class Error\b"),
    ("error_code", "decl", "error.hpp", r"^enum class ErrorCode\b"),
    ("error_codes", "enum", "error.hpp", r"^enum class ErrorCode\b"),
    ("fit_result", "decl", "fit.hpp", r"^struct FitResult\b"),
    ("result_options", "decl", "fit.hpp", r"^\s*nlohmann::json options = "),
    ("result_points", "decl", "fit.hpp", r"^\s*std::vector<Point> points;\s*///<"),
    ("result_knots", "decl", "fit.hpp", r"^\s*std::vector<double> knots;\s*///<"),
    ("result_tangents", "decl", "fit.hpp", r"^\s*std::vector<Vec2> tangents;\s*///<"),
    ("report", "decl", "fit.hpp", r"^struct Report\b"),
    ("report_level", "decl", "fit.hpp", r"^enum class ReportLevel\b"),
    ("report_levels", "enum", "fit.hpp", r"^enum class ReportLevel\b"),
    ("input_alpha", "decl", "fit.hpp", r"^\s*double alpha = kDefaultAlpha;"),
    ("fit_options_accuracy", "decl", "fit.hpp", r"^\s*std::optional<double> accuracy\{\};"),
    ("fit_options_best_effort", "decl", "fit.hpp", r"^\s*bool best_effort = false;"),
    ("fit_options_diagnostics", "decl", "fit.hpp", r"^\s*bool diagnostics = true;"),
    ("fit_options_time_limit", "decl", "fit.hpp", r"^\s*std::optional<double> time_limit\{\};"),
    ("fit_options_progress", "decl", "fit.hpp", r"^\s*std::function<bool\(const FitProgress&\)> progress\{\};"),
    ("input_knots", "decl", "fit.hpp", r"^\s*std::vector<double> knots;\s*$"),
    ("input_tangents", "decl", "fit.hpp", r"^\s*std::vector<std::optional<Vec2>> tangents;"),
    ("input_kinds", "decl", "fit.hpp", r"^\s*std::vector<PointKind> kinds;"),
    ("input_states", "decl", "fit.hpp", r"^\s*std::vector<NodeState> states;"),
    ("input_side_tangents", "decl", "fit.hpp", r"^\s*std::vector<std::optional<Vec2>> in_tangents, out_tangents;"),
    ("input_corners_deg", "decl", "fit.hpp", r"^\s*std::vector<double> corners_deg;"),
    ("input_radii", "decl", "fit.hpp", r"^\s*std::vector<double> radii;"),
    ("side_states", "enum", "fit.hpp", r"^enum class SideState\b"),
    ("input_start_tangent", "decl", "fit.hpp", r"^\s*std::optional<Vec2> start_tangent;"),
    ("point_kind", "decl", "fit.hpp", r"^enum class PointKind\b"),
    ("point_kinds", "enum", "fit.hpp", r"^enum class PointKind\b"),
    ("segment", "decl", "spline.hpp", r"^struct Segment\b"),
    ("spline_range", "decl", "spline.hpp", r"^\s*double t_begin\(\) const;"),
    ("spline_eval", "decl", "spline.hpp", r"^\s*Point eval\(double t\) const;"),
    ("spline_derivative", "decl", "spline.hpp", r"^\s*Vec2 derivative\(double t,"),
    ("spline_curvature", "decl", "spline.hpp", r"^\s*double curvature\(double t\) const;"),
    ("spline_sample", "decl", "spline.hpp", r"^\s*std::vector<Point> sample\("),
    ("bezier_curvature", "decl", "cubic_bezier.hpp", r"^\s*double curvature\(double u\) const;"),
    ("to_json", "decl", "io/json.hpp", r"^nlohmann::json to_json\(const FitResult& result\);"),
    ("write_svg", "decl", "io/svg.hpp", r"^std::string write_svg\("),
    ("geometry_length", "decl", "geometry.hpp", r"^double length\("),
    ("geometry_length_accuracy", "decl", "geometry.hpp", r"^inline constexpr double kDefaultLengthAccuracy"),
    ("geometry_segment_lengths", "decl", "geometry.hpp", r"^std::vector<double> segment_lengths\("),
    ("geometry_lengths_at", "decl", "geometry.hpp", r"^std::vector<double> lengths_at\("),
    ("geometry_parameters_at_lengths", "decl", "geometry.hpp", r"^std::vector<double> parameters_at_lengths\("),
    ("geometry_equal_length_parameters", "decl", "geometry.hpp", r"^std::vector<double> equal_length_parameters\("),
    ("geometry_flatten", "decl", "geometry.hpp", r"^Polyline flatten\("),
    ("geometry_bounds", "decl", "geometry.hpp", r"^BBox bounds\("),
    ("geometry_project", "decl", "geometry.hpp", r"^Projection project\("),
    ("geometry_frame", "decl", "geometry.hpp", r"^struct Frame\b"),
    ("geometry_split", "decl", "geometry.hpp", r"^std::pair<Spline, Spline> split\("),
    ("geometry_subcurve", "decl", "geometry.hpp", r"^Spline subcurve\("),
    ("geometry_reversed", "decl", "geometry.hpp", r"^Spline reversed\("),
    ("geometry_affine", "decl", "geometry.hpp", r"^struct Affine\b"),
    ("geometry_transformed", "decl", "geometry.hpp", r"^Spline transformed\("),
    ("svg_path_data", "decl", "io/paths.hpp", r"^std::string svg_path_data\("),
    ("write_geojson", "decl", "io/paths.hpp", r"^std::string write_geojson\(const FitResult"),
    ("keep_fit_memory", "decl", "fit.hpp", r"^void keep_fit_memory\("),
    ("parse_curve_ensemble", "decl", "io/curve_ensemble.hpp", r"^FitInput parse_curve_ensemble\("),
    ("write_curve_ensemble", "decl", "io/curve_ensemble.hpp", r"^std::string write_curve_ensemble\("),
    ("svg_options", "decl", "io/svg.hpp", r"^struct SvgOptions\b"),
    ("set_svg_option", "decl", "io/svg.hpp", r"^void set_svg_option\("),
    ("svg_width", "decl", "io/svg.hpp", r"^\s*double width = "),
    ("svg_height", "decl", "io/svg.hpp", r"^\s*double height = "),
    ("svg_margin", "decl", "io/svg.hpp", r"^\s*double margin = "),
    ("svg_points", "decl", "io/svg.hpp", r"^\s*bool points = "),
    ("svg_control_polygon", "decl", "io/svg.hpp", r"^\s*bool control_polygon = "),
    ("svg_comb", "decl", "io/svg.hpp", r"^\s*bool comb = "),
    ("svg_comb_scale", "decl", "io/svg.hpp", r"^\s*double comb_scale = "),
    ("svg_comb_samples", "decl", "io/svg.hpp", r"^\s*int comb_samples_per_segment = "),
    ("svg_caption", "decl", "io/svg.hpp", r"^\s*bool caption = "),
]

DOC_LINE = re.compile(r"^\s*///(?!<)\s?(.*)$")
TRAILING = re.compile(r"///<\s?(.*)$")
CONTINUATION = re.compile(r"^\s*///<\s?(.*)$")
ENUMERATOR = re.compile(r"^\s*(k[A-Za-z0-9]+)\s*(?:=\s*[^,]*)?,?\s*///<\s?(.*)$")


class GenError(Exception):
    pass


def find_line(lines, pattern, header):
    rx = re.compile(pattern)
    hits = [i for i, line in enumerate(lines) if rx.search(line)]
    if len(hits) != 1:
        raise GenError("{}: /{}/ matches {} lines (expected exactly one)".format(
            header, pattern, len(hits)))
    return hits[0]


def decl_doc(lines, i):
    above = []
    j = i - 1
    while j >= 0:
        m = DOC_LINE.match(lines[j])
        if not m:
            break
        above.append(m.group(1).rstrip())
        j -= 1
    above.reverse()
    trailing = TRAILING.search(lines[i])
    if trailing:
        above.append(trailing.group(1).rstrip())
    return "\n".join(above)


def file_doc(lines):
    out = []
    for line in lines:
        if line.startswith("#pragma"):
            break
        if line.startswith("//"):
            out.append(line[2:].strip())
        elif out:
            break
    return "\n".join(out)


def snake(name):
    return re.sub(r"(?<!^)(?=[A-Z])", "_", name[1:]).lower()


def enum_doc(lines, i):
    out = []
    for line in lines[i + 1:]:
        if line.strip().startswith("}"):
            break
        m = ENUMERATOR.match(line)
        if m:
            out.append((snake(m.group(1)), m.group(2).rstrip()))
            continue
        more = CONTINUATION.match(line)
        if more and out:  # an enumerator's comment continued on the next line
            out[-1] = (out[-1][0], out[-1][1] + " " + more.group(1).rstrip())
    if not out:
        raise GenError("enum on line {} has no documented enumerators".format(i + 1))
    width = max(len(name) for name, _ in out)
    return "\n".join("  {}  {}".format(name.ljust(width), doc) for name, doc in out)


CONSTANT = re.compile(r"constexpr\s+[\w:]+\s+(k[A-Z]\w*)\s*=\s*([^;]+);")


def header_constants(include_dir):
    """{kName: value text} of every `constexpr T kName = value;` in the public headers."""
    out = {}
    for root, _, names in os.walk(os.path.join(include_dir, "fairspline")):
        for name in names:
            with open(os.path.join(root, name), encoding="utf-8") as f:
                for m in CONSTANT.finditer(f.read()):
                    out[m.group(1)] = m.group(2).strip()
    return out


def pythonize(text, constants):
    """The C++ comment in a Python user's words: no C++ names, types or `Throws`.

    Error(kCode) -> fairspline.Error (code "code"); Type::member -> `member`; kConstant -> its
    value; other kEnumerators -> "snake_case" (the JSON/Python spelling); nullopt -> None.
    """
    text = re.sub(r"\bError\((k[A-Z]\w*)\)",
                  lambda m: 'fairspline.Error (code "{}")'.format(snake(m.group(1))), text)
    text = text.replace("std::thread::hardware_concurrency()", "the number of cores")
    text = re.sub(r"\bfairspline::(\w+)", r"fairspline.\1", text)
    text = re.sub(r"\b[A-Z]\w*::(\w+)", r"`\1`", text)
    text = re.sub(r"\bk[A-Z]\w*\b",
                  lambda m: constants.get(m.group(0), '"{}"'.format(snake(m.group(0)))), text)
    text = re.sub(r"\b(std::)?nullopt\b", "None", text)
    text = re.sub(r"\bThrows\b", "Raises", text)
    text = re.sub(r"\bthrows\b", "raises", text)
    return text.replace("``", "`")


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    include_dir, output = argv[1], argv[2]
    cache = {}
    entries = []
    constants = header_constants(include_dir)
    try:
        for key, kind, header, pattern in SYMBOLS:
            path = os.path.join(include_dir, "fairspline", header)
            if path not in cache:
                with open(path, encoding="utf-8") as f:
                    cache[path] = f.read().splitlines()
            lines = cache[path]
            if kind == "file":
                text = file_doc(lines)
            else:
                i = find_line(lines, pattern, header)
                text = decl_doc(lines, i) if kind == "decl" else enum_doc(lines, i)
            if not text:
                raise GenError("{}: no doc comment for /{}/ ({})".format(header, pattern, key))
            text = pythonize(text, constants)
            if ")fsdoc\"" in text:
                raise GenError("{}: doc of {} contains the raw-string delimiter".format(
                    header, key))
            entries.append((key, header, text))
    except (GenError, OSError) as e:
        sys.stderr.write("gen_docstrings: {}\n".format(e))
        return 1

    parts = [
        "// Generated by python/gen_docstrings.py from the public headers' doc comments.\n",
        "// Do not edit: edit the comments in include/fairspline/ instead.\n",
        "#pragma once\n\nnamespace fairspline_py::doc {\n",
    ]
    for key, header, text in entries:
        parts.append("// {}\ninline constexpr const char {}[] = R\"fsdoc({})fsdoc\";\n".format(
            header, key, text))
    parts.append("}  // namespace fairspline_py::doc\n")
    content = "".join(parts)
    os.makedirs(os.path.dirname(os.path.abspath(output)), exist_ok=True)
    with open(output, "w", encoding="utf-8") as f:
        f.write(content)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
