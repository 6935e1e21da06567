"""Length balancing is defined once (core.conventions: ``BALANCE`` = diag of S for
stiffnesses and wrenches, ``TWIST_BALANCE`` = 1 / BALANCE for twists, and the direction
names) and every site that balances uses it: each test computes one balanced quantity by
hand from BALANCE and compares it with the site's output (issue 27, item 15). The
twists are chosen so that using the wrong one of the two (or none) changes the answer."""

from __future__ import annotations

import json

import numpy as np
import pytest

from ppm_stiffness.cli import main
from ppm_stiffness.core import conventions
from ppm_stiffness.core.conventions import BALANCE, DIRECTION_NAMES, LENGTH_SCALE, TWIST_BALANCE
from ppm_stiffness.dynamics import condensation, modes
from ppm_stiffness.statics import margin
from ppm_stiffness.statics.moving_core import _balanced_norm
from ppm_stiffness.visuals.modes import _view

#: A twist (rad, m) whose largest component is the rotation, but whose largest balanced
#: component (omega L = 0.03 m against 0.04 m) is the x translation.
TWIST = np.array([0.3, 0.0, 0.0, 0.04, 0.0, 0.0])


def test_the_twist_balance_is_the_inverse_of_the_stiffness_balance() -> None:
    np.testing.assert_array_equal(BALANCE, [1 / LENGTH_SCALE] * 3 + [1.0] * 3)
    # bit for bit the (L, L, L, 1, 1, 1) the sites built before
    np.testing.assert_array_equal(TWIST_BALANCE, [LENGTH_SCALE] * 3 + [1.0] * 3)
    np.testing.assert_array_equal(BALANCE * TWIST_BALANCE, 1.0)


def test_direction_names_are_defined_once() -> None:
    assert modes.DIRECTION_NAMES is DIRECTION_NAMES
    assert margin.DIRECTION_NAMES is DIRECTION_NAMES
    assert conventions.TWIST_COMPONENTS == ("phi_x", "phi_y", "phi_z", "x", "y", "z")
    axes = [n.split()[-1] if n.startswith("rotation") else n.split()[0] for n in DIRECTION_NAMES]
    assert axes == ["x", "y", "z", "x", "y", "z"]  # in twist order


def test_condensation_uses_the_twist_balance() -> None:
    """The passive rates' least squares weights twists as (omega L, v): its module has
    no balance of its own."""
    assert condensation.TWIST_BALANCE is TWIST_BALANCE
    assert not any("BALANCE" in name and name != "TWIST_BALANCE" for name in vars(condensation))


def test_dominant_direction_and_normalised_shape_are_balanced_twists() -> None:
    balanced = TWIST / BALANCE  # (omega L, v) by hand: (0.03, 0, 0, 0.04, 0, 0) m
    index, share = modes.dominant_direction(TWIST)
    assert DIRECTION_NAMES[index] == "x translation"
    assert share == pytest.approx(0.04**2 / (0.03**2 + 0.04**2), rel=1e-15)  # 0.64
    shape = modes.normalised_shape(TWIST)
    np.testing.assert_allclose(shape, TWIST / np.linalg.norm(balanced), rtol=1e-15)
    assert np.linalg.norm(shape / BALANCE) == pytest.approx(1.0, rel=1e-15)


def test_margin_names_a_mode_by_its_balanced_twist() -> None:
    assert margin.mode_name(TWIST) == "x translation"


def test_mode_panel_view_is_chosen_on_the_balanced_twist() -> None:
    """A planar panel is drawn from above unless the balanced out-of-plane part (rx, ry,
    z) is more than half the balanced norm squared: 0.03^2 of 0.05^2 here (36 %)."""
    assert _view(TWIST, planar=True) == "top"
    tilted = np.array([0.5, 0.0, 0.0, 0.04, 0.0, 0.0])  # 0.05^2 of 0.05^2 + 0.04^2: 61 %
    assert _view(tilted, planar=True) == "side y-z"


def test_moving_geometry_balances_wrenches_as_m_over_l_and_f() -> None:
    wrench = np.array([[0.5, 0.0, 0.0, 3.0, 0.0, 0.0], [0.0, 0.2, 0.0, 0.0, -3.0, 0.0]])
    by_hand = np.max(np.abs(wrench * BALANCE), axis=-1)  # (m / L, f): 5 N and 3 N
    np.testing.assert_array_equal(_balanced_norm(wrench), by_hand)
    np.testing.assert_array_equal(by_hand, [5.0, 3.0])


def test_modes_table_prints_balanced_shapes(capsys: pytest.CaptureFixture[str]) -> None:
    """``modes`` prints each shape as (omega L, v) to 3 decimals: the 3-PRS's first mode
    is x with a tilt about y (3.43 rad per m, printed +0.343 at L = 0.1 m)."""
    design = ["--design", "examples/3prs.toml"]
    assert main(["modes", *design, "--json"]) == 0
    shapes = [m["shape"] for m in json.loads(capsys.readouterr().out)["modes"]]
    assert main(["modes", *design]) == 0
    text = capsys.readouterr().out
    rows = [line for line in text.splitlines() if line.startswith("│")][-len(shapes) :]
    for row, shape in zip(rows, shapes, strict=True):
        printed = [float(cell) for cell in row.strip("│ ").split("│")[1:]]
        by_hand = np.asarray(shape) / BALANCE
        np.testing.assert_allclose(printed, by_hand, rtol=0, atol=5e-4 + 1e-12)
    assert abs(np.asarray(shapes[0])[1] / BALANCE[1]) > 0.3  # a balanced rotation is shown
