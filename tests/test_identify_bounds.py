"""``identify`` at the edge of its search range (issue 27, item 4): a measured rotation
of 90 deg put a 3-RPS actuator's k_a at exactly 1e-3 of its catalogue value with a
"standard error" of 0.0013 %. An estimate at a bound is flagged, and its standard
error is not presented as valid."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.cli import main
from ppm_stiffness.design import load_design
from ppm_stiffness.fit.identify import (
    BOUND_PROXIMITY,
    RELATIVE_BOUNDS,
    BoundWarning,
    _at_bound,
    _covariance,
    identify,
    measurement_rows,
)
from ppm_stiffness.statics.measurements import read_measurements

ROOT = Path(__file__).parents[1]
RPS = ROOT / "examples/3rps.toml"
DATA = ROOT / "examples/identification/3rps_measurements.csv"


def _rotated(tmp_path: Path) -> Path:
    """The shipped 3-RPS file's first pose (6 rows), its m_x row measuring phi_x = 90 deg
    (0.075 deg in the file): an absurd rotation."""
    lines = [s for s in DATA.read_text(encoding="utf-8").splitlines() if not s.startswith("#")]
    header = lines[0].split(",")
    row = lines[4].split(",")  # the fourth data row: m_x = 50 N·m at home
    assert row[header.index("mx_Nm")] == "50" and row[header.index("pose_z_mm")] == "350"
    row[header.index("phi_x_deg")] = "90"
    path = tmp_path / "rotated.csv"
    path.write_text("\n".join([*lines[:4], ",".join(row), *lines[5:7]]) + "\n", "utf-8")
    return path


def test_an_estimate_at_the_lower_bound_is_flagged(tmp_path: Path) -> None:
    design = load_design(RPS)
    rows = measurement_rows(design, read_measurements(_rotated(tmp_path)))
    assert rows.n_rows == 6
    with pytest.warns(BoundWarning, match="leg1.actuator.k_a is at the lower bound"):
        result = identify(design, rows, ["leg1.actuator.k_a"])
    assert result.values[0] == pytest.approx(RELATIVE_BOUNDS[0] * 60e6, rel=1e-9)
    assert result.at_bound == {"leg1.actuator.k_a": "lower"}
    assert math.isnan(result.standard_errors[0]) and math.isnan(result.correlation[0, 0])
    assert "no valid standard error" in result.bound_messages()[0]
    # nor a combination: the only one weighed on k_a and gave it a relative sigma
    # of 1.3e-5 as if it were determined
    assert result.combinations == []


def test_a_fit_inside_the_range_is_not_flagged() -> None:
    design = load_design(RPS)
    rows = measurement_rows(design, read_measurements(DATA))
    result = identify(design, rows, ["leg1.actuator.k_a", "leg*.base_revolute.tilt"])
    assert result.at_bound == {} and np.all(np.isfinite(result.standard_errors))


def test_at_bound_within_the_proximity() -> None:
    lo, hi = np.array([1e-3] * 4), np.array([1e3] * 4)
    theta = np.array([1e-3 * (1 + BOUND_PROXIMITY), 1e-3 * (1 + 2 * BOUND_PROXIMITY), 1.0, 999.0])
    names = ["a", "b", "c", "d"]
    assert _at_bound(names, theta, lo, hi) == {"a": "lower", "d": "upper"}
    unbounded = np.full(4, np.inf)
    assert _at_bound(names, theta, -unbounded, unbounded) == {}


def test_the_others_covariance_holds_the_bound_one_fixed() -> None:
    """Two parameters, the second at a bound: the first's 1-sigma is that of a fit of
    it alone, 1 / |J[:, 0]| (closed form), and the second's is NaN."""
    jac = np.array([[1.0, 0.5], [0.0, 2.0], [2.0, 1.0]])
    se, corr = _covariance(jac, np.array([True, False]))
    assert se[0] == pytest.approx(1 / math.sqrt(5.0), rel=1e-14) and math.isnan(se[1])
    assert corr[0, 0] == pytest.approx(1.0) and np.isnan(corr[[0, 1, 1], [1, 0, 1]]).all()
    # both free: the usual (J^T J)^-1
    se, _ = _covariance(jac, np.array([True, True]))
    np.testing.assert_allclose(se, np.sqrt(np.diag(np.linalg.inv(jac.T @ jac))), rtol=1e-12)


def test_the_table_and_the_json_flag_it(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    jsonschema = pytest.importorskip("jsonschema")
    argv = ["identify", "--design", str(RPS), "--measurements", str(_rotated(tmp_path))]
    argv += ["--free", "leg1.actuator.k_a"]
    assert main(argv) == 0
    out, err = capsys.readouterr()
    text = " ".join(out.split())
    assert "at lower bound" in text and "warning: leg1.actuator.k_a is at the lower" in text
    assert "ppm-stiffness: warning: leg1.actuator.k_a is at the lower bound" in err
    assert "no combination includes leg1.actuator.k_a: at a bound of the search" in text
    assert "weakest combination" not in text
    assert main([*argv, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    (p,) = doc["parameters"]
    assert p["standard_error"] is None and p["at_bound"] == "lower"
    assert p["estimate"] == pytest.approx(60e3, rel=1e-9)
    assert doc["correlation"] == [[None]] and "the bound" in doc["warnings"][0]
    assert doc["combinations"] == []
    spec = json.loads((ROOT / "docs/schemas/identify.schema.json").read_text("utf-8"))
    jsonschema.validate(doc, spec, cls=jsonschema.Draft202012Validator)
