"""The error catalog (docs/errors.md, tests/data/errors.json) in Python: every entry with a
"python" form raises fairspline.Error with the catalog's code, index and message. The same
entries are checked in C++, the CLI and the web API by tests/error_test.cpp."""

import json
import math

import pytest

import fairspline
from conftest import SOURCE_DIR

CATALOG = json.loads((SOURCE_DIR / "tests" / "data" / "errors.json").read_text())["entries"]
PYTHON_ENTRIES = [e for e in CATALOG if "python" in e]


def as_floats(value):
    """The catalog writes non-finite numbers as the strings "inf" and "nan" (JSON has none)."""
    if isinstance(value, list):
        return [as_floats(v) for v in value]
    if value in ("inf", "nan"):
        return float(value)
    return value


def test_every_code_reachable_from_python_is_covered():
    # parse_error (Python takes arrays, not text) and io_error (no files) have no Python form.
    codes = {e["code"] for e in CATALOG} - {"parse_error", "io_error"}
    assert codes <= {e["code"] for e in PYTHON_ENTRIES}


@pytest.mark.parametrize("entry", PYTHON_ENTRIES, ids=lambda e: f"{e['code']}-{e['index']}")
def test_catalog_entry(entry):
    kwargs = {k: as_floats(v) for k, v in entry["python"].items()}
    points = kwargs.pop("points")
    with pytest.raises(fairspline.Error) as info:
        fairspline.fit(points, **kwargs)
    error = info.value
    assert isinstance(error, ValueError)
    assert error.code == entry["code"]
    assert error.index == entry["index"]
    assert entry.get("python_message", entry["message"]) in str(error)
    if entry["index"] is None:
        assert error.index is None
    else:
        assert isinstance(error.index, int) and not isinstance(error.index, bool)
        assert not math.isnan(error.index)
