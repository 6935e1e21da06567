"""A leg's points as scalar design parameters (issue 31, item 1): x, y, z, radius and
angle of a chain leg's joint ``point`` and of a preset's ``base_point`` and
``platform_point`` (:mod:`ppm_stiffness.design.points`)."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.cli import main
from ppm_stiffness.core.errors import DesignError, InputDataError
from ppm_stiffness.design import Design, design_from_dict, load_design
from ppm_stiffness.model import stiffness_at_pose
from ppm_stiffness.optimize.variables import parse_variable

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
S_POINTS = "leg*.platform_joint.point"


def _s_points(design: object) -> np.ndarray:
    return np.array([leg.elements[-1].point for leg in design.legs])  # type: ignore[attr-defined]


def test_glob_radius_scales_every_s_point_keeping_angle_and_z() -> None:
    design = load_design(EXAMPLES / "6rus.toml")
    before = _s_points(design)
    after = _s_points(design.with_parameters({f"{S_POINTS}.radius": 0.11}))
    assert len(before) == 6  # the file's pattern leg, stored as its six copies
    np.testing.assert_allclose(np.hypot(after[:, 0], after[:, 1]), 0.11, rtol=0, atol=1e-15)
    angle = np.arctan2(before[:, 1], before[:, 0])
    np.testing.assert_allclose(np.arctan2(after[:, 1], after[:, 0]), angle, rtol=0, atol=1e-15)
    assert np.array_equal(after[:, 2], before[:, 2])


def test_radius_set_equals_the_file_edited_by_hand() -> None:
    """The glob on the loaded copies gives the K of the pattern leg edited in the file:
    the copies keep the pattern's symmetry."""
    raw = tomllib.loads((EXAMPLES / "6rus.toml").read_text("utf-8"))
    design = design_from_dict(raw)
    joint = raw["legs"][0]["elements"][-1]
    x, y, z = joint["point"]
    scale = 0.11 / math.hypot(x, y)
    joint["point"] = [x * scale, y * scale, z]
    by_hand = stiffness_at_pose(design_from_dict(raw))
    by_name = stiffness_at_pose(design.with_parameters({f"{S_POINTS}.radius": 0.11}))
    unchanged = stiffness_at_pose(design)
    scale_k = np.abs(by_hand).max()
    assert np.abs(by_name - by_hand).max() < 1e-12 * scale_k
    assert np.abs(unchanged - by_hand).max() > 1e-3 * scale_k  # the change matters


def test_one_leg_of_a_pattern_moves_that_copy_only() -> None:
    design = load_design(EXAMPLES / "6rus.toml")
    after = design.with_parameters({"leg1.platform_joint.point.z": 0.2})
    assert after.legs[0].elements[-1].point[2] == 0.2
    assert [leg.elements for leg in after.legs[1:]] == [leg.elements for leg in design.legs[1:]]


def test_angle_of_a_hexapod_platform_point() -> None:
    design = load_design(EXAMPLES / "hexapod_6ups.toml")
    x, y, z = design.legs[0].platform_point
    assert design.parameter("leg1.platform_point.angle") == math.atan2(y, x)
    moved = design.with_parameters({"leg1.platform_point.angle": 0.9})
    px, py, pz = moved.legs[0].platform_point
    assert abs(math.atan2(py, px) - 0.9) < 1e-15
    assert abs(math.hypot(px, py) - math.hypot(x, y)) < 1e-15
    assert pz == z
    assert moved.legs[1:] == design.legs[1:]
    assert moved.parameter_unit("leg1.platform_point.angle") == "rad"


def test_listing_names_the_components_with_units(capsys: pytest.CaptureFixture[str]) -> None:
    design = load_design(EXAMPLES / "6rus.toml")
    names = design.scalar_parameter_names()
    for key, unit in (("x", "m"), ("y", "m"), ("z", "m"), ("radius", "m"), ("angle", "rad")):
        assert f"leg6.crank_joint.point.{key}" in names
        assert design.parameter_unit(f"leg*.crank_joint.point.{key}") == unit
    # an axis gets its two angles only (module doc of design.points)
    axis_names = {n.rsplit(".", 1)[1] for n in names if ".axis" in n}
    assert axis_names == {"tilt", "azimuth"}
    assert design.parameter_unit("leg1.crank_joint.axis2.azimuth") == "rad"
    assert design.parameter_unit("platform.radius") == "m"  # the disk's, not a point's
    code = main(["calibrate", "--list-parameters", "--design", str(EXAMPLES / "6rus.toml")])
    out = capsys.readouterr().out
    assert code == 0
    row = next(line for line in out.splitlines() if "leg1.crank_drive.point.radius" in line)
    assert "0.15" in row and "m" in row
    row = next(line for line in out.splitlines() if "leg1.crank_drive.point.angle" in line)
    assert "-0.349066" in row and "rad" in row


@pytest.mark.parametrize(
    "name", ["leg1.crank_joint.point.w", "leg1.crank_joint.axis.x", "leg1.base_point.z"]
)
def test_bad_names_refused(name: str) -> None:
    design = load_design(EXAMPLES / ("6rus.toml" if "crank" in name else "3rpr.toml"))
    with pytest.raises(DesignError, match="unknown design parameter"):
        design.with_parameters({name: 0.1})


def test_bad_values_refused() -> None:
    design = load_design(EXAMPLES / "hexapod_6ups.toml")
    with pytest.raises(DesignError, match=r"radius .*>= 0 m"):
        design.with_parameters({"leg1.base_point.radius": -0.1})
    with pytest.raises(DesignError, match="did you mean"):  # 150 m: a length in mm
        design.check_value("leg1.base_point.radius", 150.0)


def test_vary_takes_a_point_component_and_refuses_a_coupled_pair() -> None:
    design = load_design(EXAMPLES / "hexapod_6ups.toml")
    v = parse_variable("leg*.base_point.radius=0.14:0.16", design)
    assert v.unit == "m" and len(v.matches) == 18  # six radii with their x and y
    assert parse_variable("leg1.base_point.x=0.1:0.2", design).matches == ("leg1.base_point.x",)
    with pytest.raises(InputDataError, match="refused by the design"):
        parse_variable("leg1.base_point.radius=-0.1:0.2", design)
    from ppm_stiffness.optimize.variables import check_distinct

    pair = [
        parse_variable(t, design)
        for t in ("leg1.base_point.x=0.1:0.2", "leg1.base_point.radius=0.1:0.2")
    ]
    with pytest.raises(InputDataError, match="both set parameter 'leg1.base_point.x'"):
        check_distinct(pair)


def test_point_radius_glob_equals_the_geometric_variable() -> None:
    """``leg*.platform_point.radius`` is ``platform_radius`` (optimize/variables.py's
    radial scaling, an independent code path) on the hexapod's joint circle, and the two
    are refused together."""
    from ppm_stiffness.optimize.variables import apply_values, check_distinct

    design = load_design(EXAMPLES / "hexapod_6ups.toml")
    a = stiffness_at_pose(apply_values(design, {"platform_radius": 0.12}))
    b = stiffness_at_pose(design.with_parameters({"leg*.platform_point.radius": 0.12}))
    assert np.abs(a - b).max() < 1e-12 * np.abs(a).max()
    pair = [
        parse_variable(t, design)
        for t in ("platform_radius=0.1:0.2", "leg2.platform_point.radius=0.1:0.2")
    ]
    with pytest.raises(InputDataError, match="both set parameter 'leg2.platform_point.radius'"):
        check_distinct(pair)


@pytest.mark.parametrize(
    ("example", "name", "radius"),
    [
        ("3prs.toml", "leg*.platform_point.radius", 0.15),
        ("delta.toml", "leg*.forearm.far.radius", 0.05),
        ("tricept.toml", "leg*.base_joint.point.radius", 0.22),
    ],
)
def test_a_glob_reads_radii_equal_but_for_rounding(example: str, name: str, radius: float) -> None:
    """The legs' points on one circle, turned by cos and sin: one radius (the first)."""
    design = load_design(EXAMPLES / example)
    assert design.parameter(name) == pytest.approx(radius, rel=1e-14)
    with pytest.raises(DesignError, match="its matches differ"):
        design.parameter(name.replace("radius", "angle"))


DRIVE_AXES = "leg*.crank_drive.axis"


def _pattern_crank_tilted(tilt: float) -> tuple[Design, Design]:
    """The 6-RUS as shipped, and as its file with the pattern leg's crank axis turned in
    its vertical plane to ``tilt`` [rad] (its azimuth kept)."""
    raw = tomllib.loads((EXAMPLES / "6rus.toml").read_text("utf-8"))
    design = design_from_dict(raw)
    drive = raw["legs"][0]["elements"][0]
    x, y, _ = drive["axis"]
    azimuth = math.atan2(y, x)
    s = math.sin(tilt)
    drive["axis"] = [s * math.cos(azimuth), s * math.sin(azimuth), math.cos(tilt)]
    return design, design_from_dict(raw)


def test_axis_angles_are_the_axis_spherical_angles() -> None:
    design = load_design(EXAMPLES / "6rus.toml")
    for i, leg in enumerate(design.legs, start=1):
        a = np.asarray(leg.elements[0].axis, dtype=float)
        tilt = design.parameter(f"leg{i}.crank_drive.axis.tilt")
        azimuth = design.parameter(f"leg{i}.crank_drive.axis.azimuth")
        assert tilt == pytest.approx(math.acos(a[2] / np.linalg.norm(a)), abs=1e-15)
        assert azimuth == pytest.approx(math.atan2(a[1], a[0]), abs=1e-15)


def test_a_glob_moves_a_pattern_s_axes_as_the_pattern_does() -> None:
    """The 6-RUS pattern's mirrored copies carry their crank axes reversed: tilting the
    pattern leg's axis to 1.3 rad in the file tilts a mirrored copy's to pi - 1.3. The
    glob sets the first match and moves the copies as the pattern does: the K of the
    file edited by hand to 1e-12, tilt and azimuth alike (one tilt for all six would
    be 1.6 % off in K)."""
    design, edited = _pattern_crank_tilted(1.3)
    assert edited.parameter("leg2.crank_drive.axis.tilt") == pytest.approx(math.pi - 1.3)
    by_hand = stiffness_at_pose(edited)
    by_glob = stiffness_at_pose(design.with_parameters({f"{DRIVE_AXES}.tilt": 1.3}))
    scale_k = np.abs(by_hand).max()
    assert np.abs(by_glob - by_hand).max() < 1e-12 * scale_k
    names = [f"leg{i}.crank_drive.axis.tilt" for i in range(1, 7)]
    alike = design.with_parameters(dict.fromkeys(names, 1.3))  # not the pattern
    assert np.abs(stiffness_at_pose(alike) - by_hand).max() > 1e-3 * scale_k
    assert design.parameter(f"{DRIVE_AXES}.tilt") == pytest.approx(math.pi / 2, abs=1e-15)
    assert edited.parameter(f"{DRIVE_AXES}.tilt") == pytest.approx(1.3, abs=1e-9)
    # the azimuth: the pattern leg's axis turned about z by 0.1 rad in the file
    raw = tomllib.loads((EXAMPLES / "6rus.toml").read_text("utf-8"))
    drive = raw["legs"][0]["elements"][0]
    x, y, z = drive["axis"]
    c, s = math.cos(0.1), math.sin(0.1)
    drive["axis"] = [c * x - s * y, s * x + c * y, z]
    turned = stiffness_at_pose(design_from_dict(raw))
    start = design.parameter(f"{DRIVE_AXES}.azimuth")  # the first match's
    assert start == pytest.approx(math.atan2(y, x), abs=1e-9)
    by_glob = stiffness_at_pose(design.with_parameters({f"{DRIVE_AXES}.azimuth": start + 0.1}))
    assert np.abs(by_glob - turned).max() < 1e-12 * np.abs(turned).max()
    assert np.abs(turned - stiffness_at_pose(design)).max() > 1e-3 * np.abs(turned).max()


def test_a_glob_over_legs_that_are_not_copies_is_refused() -> None:
    """One leg moved by hand is no copy of the first: no symmetry to keep."""
    design = load_design(EXAMPLES / "6rus.toml").with_parameters({"leg3.crank_joint.point.z": 0.01})
    with pytest.raises(DesignError, match="not a turned or mirrored copy"):
        design.with_parameters({f"{DRIVE_AXES}.tilt": 1.3})
    with pytest.raises(DesignError, match="not a turned or mirrored copy"):
        design.parameter(f"{DRIVE_AXES}.tilt")
    assert design.parameter("leg3.crank_drive.axis.tilt") == pytest.approx(math.pi / 2)


def test_tilt_set_leg_by_leg_equals_the_file_edited_by_hand() -> None:
    """Setting each copy's tilt as the edited pattern gives it (1.3, or pi - 1.3 for a
    mirrored copy) is the K of the pattern leg's axis turned in its vertical plane in
    the file."""
    design, edited = _pattern_crank_tilted(1.3)
    by_hand = stiffness_at_pose(edited)
    names = [f"leg{i}.crank_drive.axis.tilt" for i in range(1, 7)]
    by_name = stiffness_at_pose(design.with_parameters({n: edited.parameter(n) for n in names}))
    unchanged = stiffness_at_pose(design)
    scale_k = np.abs(by_hand).max()
    assert np.abs(by_name - by_hand).max() < 1e-12 * scale_k
    assert np.abs(unchanged - by_hand).max() > 1e-3 * scale_k  # the change matters


def test_tilt_and_azimuth_commute_and_keep_the_length() -> None:
    design = load_design(EXAMPLES / "6rus.toml")
    a = design.with_parameters(
        {"leg2.crank_drive.axis.tilt": 1.2, "leg2.crank_drive.axis.azimuth": 0.4}
    )
    b = design.with_parameters(
        {"leg2.crank_drive.axis.azimuth": 0.4, "leg2.crank_drive.axis.tilt": 1.2}
    )
    axis = np.asarray(a.legs[1].elements[0].axis, dtype=float)
    np.testing.assert_allclose(axis, b.legs[1].elements[0].axis, rtol=0, atol=1e-15)
    length = np.linalg.norm(design.legs[1].elements[0].axis)  # 1 to the file's 10 digits
    expected = [math.sin(1.2) * math.cos(0.4), math.sin(1.2) * math.sin(0.4), math.cos(1.2)]
    np.testing.assert_allclose(axis, length * np.array(expected), rtol=0, atol=1e-15)


def test_bad_axis_angles_are_refused() -> None:
    design = load_design(EXAMPLES / "6rus.toml")
    with pytest.raises(DesignError, match=r"tilt from \+z is within \[0, pi\]"):
        design.with_parameters({"leg1.crank_drive.axis.tilt": 4.0})
    vertical = design.with_parameters({"leg1.crank_drive.axis.tilt": 0.0})
    with pytest.raises(DesignError, match="azimuth is undefined"):
        vertical.with_parameters({"leg1.crank_drive.axis.azimuth": 0.3})
    # a U's axes must stay normal: turning one of them is the design's own refusal
    with pytest.raises(DesignError, match="must be normal to axis"):
        design.with_parameters({"leg1.crank_joint.axis.tilt": 1.0})
