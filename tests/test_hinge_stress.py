"""Notch hinges' stress and range of motion (issue 29 item 3).

Model: src/ppm_stiffness/statics/hinge_stress.py; docs/flexures.md, "Stress and range of
motion".
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from ppm_stiffness.core.errors import DesignError
from ppm_stiffness.legs.flexure_hinge import FlexureHinge
from ppm_stiffness.statics.hinge_stress import (
    HingeModel,
    HingeRecord,
    hinge_model,
    peak_stress,
    stress_concentration,
)

ROOT = Path(__file__).resolve().parents[1]
MATERIAL = {"young_modulus": 71.7e9, "poisson_ratio": 0.33, "yield_strength": 503e6}
R, T, B = 2e-3, 0.3e-3, 5e-3
HINGE = {
    "profile": {"profile": "circular", "radius": R, "thickness": T},
    "width": B,
    "material": MATERIAL,
}


@pytest.fixture(scope="module")
def stage_path() -> Path:
    """The shipped 3-RRR flexure stage (equal to scripts/chain_examples.py's
    flexure_3rrr(): tested)."""
    return ROOT / "examples" / "flexure_3rrr.toml"


def single_hinge_model(centre: tuple[float, float, float]) -> HingeModel:
    """One leg made of one notch hinge (centre c from P, axis z, notch along x) whose far
    side is the platform, as the frozen model of the design's hinges."""
    from ppm_stiffness.core.solver import leg_stiffness
    from ppm_stiffness.legs.chain import Joint, leg_springs
    from ppm_stiffness.legs.types.chain_leg import JointElement

    axis, along = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
    element = JointElement(
        joint="R", point=centre, axis=tuple(axis), axis2=tuple(along), hinge=HINGE
    )
    joint = Joint(
        "R",
        axis,
        np.array(centre),
        element.stiffnesses(),
        axis2=along,
        elastic=element.elastic_stiffnesses(),
    )
    k_leg = leg_stiffness(leg_springs([joint], None))
    axes = np.column_stack([along, np.cross(axis, along), axis])
    record = HingeRecord(0, "h", FlexureHinge(**HINGE), np.array(centre), axes, 1.0, 0.0)
    return HingeModel(k_leg[None], np.zeros((1, 6)), np.zeros(1), [record])


@pytest.mark.parametrize("centre", [(0.0, 0.0, 0.0), (-0.05, 0.02, 0.0)])
def test_pure_moment_gives_the_notch_bending_stress(centre: tuple[float, float, float]) -> None:
    """A pure moment M about the hinge's axis on a single-hinge leg: its loads are
    (0, 0, M; 0) at its centre wherever it is, and its peak stress is
    K_t 6 M / (b t^2) with K_t = (1 + t / (2R))^(9/20) (Lobontiu's fit of Peterson's
    chart) at the waist; measured 6.6e-12 relative (the round-off of K K^-1 W, the
    leg's compliance has condition number 2.2e8)."""
    model = single_hinge_model(centre)
    m = 0.01  # N·m
    loads = model.hinge_loads([0.0, 0.0, m, 0.0, 0.0, 0.0], [0.0])[0]
    scale = np.array([1.0, 1.0, 1.0, 1.0 / R, 1.0 / R, 1.0 / R])  # forces as moments
    np.testing.assert_allclose(loads * scale, [0.0, 0.0, m, 0.0, 0.0, 0.0], atol=5e-11 * m)
    k_t = (1.0 + T / (2.0 * R)) ** 0.45
    assert k_t == pytest.approx(1.03307, abs=1e-5)
    sigma = model.stresses([0.0, 0.0, m, 0.0, 0.0, 0.0], [0.0])[0]
    assert sigma == pytest.approx(k_t * 6.0 * m / (B * T**2), rel=5e-11)


def test_stress_terms_and_stations() -> None:
    """Axial N / (b t) and out-of-plane 6 M_y / (t b^2) are nominal at the waist; a
    shear force V_y on a leaf of length L bends its ends by V_y L / 2 (a cantilever's
    moment), where the stress peaks: 6 V_y L / (2 b t^2)."""
    hinge = FlexureHinge(**HINGE)
    assert peak_stress(hinge, [0, 0, 0, 7.0, 0, 0]) == pytest.approx(7.0 / (B * T), rel=1e-12)
    assert peak_stress(hinge, [0, 0.02, 0, 0, 0, 0]) == pytest.approx(
        6 * 0.02 / (T * B**2), rel=1e-12
    )
    leaf = FlexureHinge(**{**HINGE, "profile": {"profile": "leaf", "length": 4e-3, "thickness": T}})
    assert stress_concentration(leaf) == 1.0
    assert peak_stress(leaf, [0, 0, 0, 0, 3.0, 0]) == pytest.approx(
        6 * 3.0 * 2e-3 / (B * T**2), rel=1e-12
    )


def test_a_profile_without_a_built_in_factor_needs_one() -> None:
    elliptic = {"profile": "elliptical", "semi_length": 2e-3, "semi_depth": 1e-3, "thickness": T}
    hinge = FlexureHinge(**{**HINGE, "profile": elliptic})
    with pytest.raises(DesignError, match="give stress_concentration"):
        stress_concentration(hinge)
    given = FlexureHinge(**{**HINGE, "profile": elliptic, "stress_concentration": 1.2})
    assert stress_concentration(given) == 1.2


@pytest.fixture(scope="module")
def stage(stage_path: Path) -> HingeModel:
    from ppm_stiffness.design import load_design

    return hinge_model(load_design(stage_path))


def test_range_is_where_the_first_hinge_reaches_the_allowed_stress(stage: HingeModel) -> None:
    """Stress is positively homogeneous in the input: at the range along a direction the
    most loaded hinge is at yield / SF to round-off (measured 4.6e-15), in both senses."""
    sf = 2.0
    limits = stage.limits(sf)
    rng = np.random.default_rng(3)
    for _ in range(3):
        wrench, inputs = rng.normal(size=6), rng.normal(size=3) * 1e-3
        sigma = stage.stresses(wrench, inputs)
        scale = np.min(limits / sigma)
        for sign in (1.0, -1.0):
            at = stage.stresses(sign * scale * wrench, sign * scale * inputs)
            assert np.max(at / limits) == pytest.approx(1.0, rel=1e-12)


def test_hinge_loads_are_in_equilibrium_with_the_leg_solve(
    stage: HingeModel, stage_path: Path
) -> None:
    """The legs' wrenches sum to the platform wrench, and every passive hinge's moment
    about its axis is k_h times its elastic rotation e from each leg's bordered solve
    (``core/solver.py``, independent of the transport): [[J C J^T, J_q, J_e],
    [J_q^T, 0, 0], [J_e^T, 0, -K_e]] [w; q; e] = [t - j dq'; 0; 0]; the driven base hinge
    carries k_h theta, theta = c_a (j^T w) + dq' its rotation (measured 1e-15 of the
    largest moment; measured 1.4e-13 at the passive hinges, the
    round-off of the bordered solve, 2e-17 at the driven one)."""
    from ppm_stiffness.design import load_design
    from ppm_stiffness.model import leg_springs_at_pose

    legs = leg_springs_at_pose(load_design(stage_path), None)
    wrench, inputs = np.array([0.1, -0.2, 0.3, 2.0, -1.0, 5.0]), np.array([1e-4, -2e-4, 0.5e-4])
    w_legs = stage.leg_wrenches(wrench, inputs)
    np.testing.assert_allclose(w_legs.sum(axis=0), wrench, atol=1e-12 * np.abs(wrench).max())
    loads = stage.hinge_loads(wrench, inputs)
    t = np.linalg.solve(
        stage.stiffness,
        wrench
        + np.einsum(
            "lij,lj,l->i", stage.leg_stiffness, stage.actuator_twists, inputs * stage.offsets
        ),
    )
    biggest = np.abs(loads[:, 2]).max()
    for i, leg in enumerate(legs):
        assert leg.elastic is not None and leg.elastic_stiffness is not None
        dq = inputs[i] * stage.offsets[i]
        jc = leg.screws @ leg.compliance @ leg.screws.T
        q, e = leg.passive, leg.elastic
        n_q, n_e = q.shape[1], e.shape[1]
        n = 6 + n_q + n_e
        a = np.zeros((n, n))
        a[:6, :6], a[:6, 6 : 6 + n_q], a[:6, 6 + n_q :] = jc, q, e
        a[6 : 6 + n_q, :6], a[6 + n_q :, :6] = q.T, e.T
        a[6 + n_q :, 6 + n_q :] = -np.diag(leg.elastic_stiffness)
        j = leg.screws[:, leg.actuator_index]
        rhs = np.concatenate([t - j * dq, np.zeros(n_q + n_e)])
        x = np.linalg.solve(a, rhs)
        np.testing.assert_allclose(x[:6], w_legs[i], rtol=1e-9, atol=1e-9 * np.abs(w_legs[i]).max())
        mine = [h for h in stage.hinges if h.leg == i]
        assert [h.name for h in mine] == ["base_hinge", "elbow_hinge", "platform_hinge"]
        moments = loads[[stage.hinges.index(h) for h in mine], 2]
        k_h = 1.0 / FlexureHinge(**HINGE).centre_compliance()[2, 2]
        theta = leg.compliance[leg.actuator_index, leg.actuator_index] * (j @ x[:6]) + dq
        assert moments[0] == pytest.approx(k_h * theta, abs=1e-12 * biggest)
        np.testing.assert_allclose(
            moments[1:], leg.elastic_stiffness * x[6 + n_q :], rtol=0, atol=1e-12 * biggest
        )


def test_analyze_prints_the_hinge_table(
    stage_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """``analyze`` on the stage: the range table and the hinge table; in JSON the range
    with SF = 2 is half that with the default SF = 1 (stress linear in the input), and
    the drive range is the allowed stress over the hinge's stress per unit input."""
    import json

    from ppm_stiffness.cli import main

    assert main(["analyze", "--design", str(stage_path)]) == 0
    out = capsys.readouterr().out
    assert "Range of motion (notch hinges" in out and "leg1.platform_hinge" in out
    docs = []
    for extra in ([], ["--safety-factor", "2"]):
        assert main(["analyze", "--design", str(stage_path), "--json", *extra]) == 0
        docs.append(json.loads(capsys.readouterr().out)["hinge_stress"])
    one, two = docs
    assert [d["name"] for d in one["directions"]] == [
        "drive 1",
        "drive 2",
        "drive 3",
        "platform x",
        "platform y",
        "platform rz",
    ]
    for a, b in zip(one["directions"], two["directions"], strict=True):
        assert b["range"] == pytest.approx(a["range"] / 2.0, rel=1e-14)
    row = one["hinges"][0]
    assert row["range"]["drive 1"] == pytest.approx(
        503e6 / row["stress_per_unit"]["drive 1"], rel=1e-14
    )


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--design", "STAGE", "--safety-factor", "0"], "--safety-factor 0: must be"),
        (
            ["--design", str(ROOT / "examples" / "delta.toml"), "--safety-factor", "2"],
            "--safety-factor: the design has no notch hinge",
        ),
    ],
)
@pytest.mark.parametrize("command", ["analyze", "deflect"])
def test_bad_safety_factor_is_refused(
    argv: list[str],
    message: str,
    command: str,
    stage_path: Path,
    capsys: pytest.CaptureFixture[str],
) -> None:
    from ppm_stiffness.cli import main

    argv = [str(stage_path) if a == "STAGE" else a for a in argv]
    assert main([command, *argv]) == 2
    captured = capsys.readouterr()
    assert message in captured.err and captured.out == ""
    assert len(captured.err.strip().splitlines()) == 1


def test_the_stage_goes_through_the_loaded_commands(
    tmp_path: Path, stage_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Its drives act in parallel with the base hinges (tests/test_flexure_loaded.py):
    ``analyze --wrench --geometry moving`` gives the library's moving state (the drives'
    forces k_p delta, not the joints'), and ``deflect`` each load's largest hinge stress
    (table, JSON, CSV), equal to the frozen hinge model's under the load (a linear law:
    the same problem, another route; measured 1.7e-15) and its utilisation at SF 2."""
    import json

    from ppm_stiffness.cli import main
    from ppm_stiffness.design import load_design
    from ppm_stiffness.statics.moving import moving_loaded_state

    design = load_design(stage_path)
    argv = ["analyze", "--design", str(stage_path), "--wrench", "30,-20,0,0,0,0.5"]
    assert main([*argv, "--geometry", "moving", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    state = moving_loaded_state(design, [0.0, 0.0, 0.5, 30.0, -20.0, 0.0])
    np.testing.assert_allclose(doc["actuator_forces"], state.actuator_forces, rtol=1e-12)
    np.testing.assert_allclose(
        doc["actuator_forces"], 5000.0 * np.asarray(doc["actuator_displacements"]), rtol=1e-12
    )
    csv = tmp_path / "curve.csv"
    deflect = ["deflect", "--design", str(stage_path), "--direction", "30,-20,0,0,0,0.5"]
    deflect += ["--max", "60", "--step", "15", "--safety-factor", "2"]
    assert main([*deflect, "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    jsonschema = pytest.importorskip("jsonschema")
    schema = (ROOT / "docs" / "schemas" / "deflect.schema.json").read_text(encoding="utf-8")
    jsonschema.validate(doc, json.loads(schema))
    hinges = doc["hinge_stress"]
    model = hinge_model(design)
    loads = np.asarray(doc["loads"])
    unit = np.asarray(doc["load_direction"])
    ref = model.stresses(loads[:, None] * unit, np.zeros((loads.size, 3)))
    worst = np.max(ref, axis=1)
    np.testing.assert_allclose(hinges["stress"], worst, rtol=1e-13, atol=1e-9)
    np.testing.assert_allclose(hinges["utilisation"], worst / (503e6 / 2.0), rtol=1e-13)
    assert hinges["hinge"][0] == "" and hinges["hinge"][-1] == "leg3.base_hinge"
    assert main([*deflect, "--csv", str(csv)]) == 0
    out = capsys.readouterr().out
    assert f"{worst[-1] / 1e6:.4g}" in out and "leg3.base_hinge" in out
    last = csv.read_text(encoding="utf-8").strip().splitlines()[-1].split(",")
    assert float(last[-2]) == pytest.approx(worst[-1] / 1e6, rel=1e-8)
    assert main([*deflect[:3], "--measurements", str(csv)]) == 0  # it reads back


def test_analyze_under_a_wrench_gives_each_hinges_stress(
    tmp_path: Path, stage_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The stage with plain driven base joints (no hinge in parallel, so that its loaded
    states apply): ``analyze --wrench`` (at a tool point off P) prints and returns each
    hinge's stress, equal to the library's under the wrench moved to P, and its
    utilisation stress / (yield / SF)."""
    import json

    from ppm_stiffness.cli import main
    from ppm_stiffness.design import design_from_dict, load_design
    from ppm_stiffness.design.io import save_design
    from ppm_stiffness.statics.hinge_stress import hinge_summary

    data = load_design(stage_path).model_dump()
    for leg in data["legs"]:
        leg["elements"][0].update(hinge=None, axis2=None)
    design = design_from_dict(data)
    path = tmp_path / "plain_drives.toml"
    save_design(design, path)
    argv = ["analyze", "--design", str(path), "--wrench", "1,-2,0,0,0,0.01"]
    assert main([*argv, "--tool-point", "5,0,0", "--safety-factor", "2", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)["hinge_stress"]
    assert [h["name"] for h in doc["hinges"][:2]] == ["elbow_hinge", "platform_hinge"]
    at_p = np.array([0.0, 0.0, 0.01 + 0.005 * -2.0, 1.0, -2.0, 0.0])
    ref = hinge_summary(design, None, at_p, 2.0)
    for mine, theirs in zip(doc["hinges"], ref["hinges"], strict=True):
        assert mine["stress"] == pytest.approx(theirs["stress"], rel=1e-12)
        assert mine["utilisation"] == pytest.approx(mine["stress"] / (503e6 / 2.0), rel=1e-14)
    assert main(argv) == 0
    printed = hinge_summary(design, None, np.array([0.0, 0.0, 0.01, 1.0, -2.0, 0.0]))
    assert f" {printed['hinges'][0]['stress'] / 1e6:.4g} " in capsys.readouterr().out


def test_a_chain_that_did_not_close_has_no_constraint_basis() -> None:
    """``map`` on the stage samples its slice's bounds far out, where a chain leg's
    closure fails and its Jacobian is NaN: the constraint basis is NaN there (the pose
    not completed) and exact elsewhere (was: LinAlgError "SVD did not converge", a
    traceback from ``ppm-stiffness map --design examples/flexure_3rrr.toml``)."""
    from ppm_stiffness.legs.kinematics import constraint_basis

    jac = np.zeros((2, 6, 3))
    jac[:, 2, 0] = jac[:, 3, 1] = jac[:, 4, 2] = 1.0  # rz, x, y: a planar chain's
    jac[1, 0, 0] = np.nan
    basis = constraint_basis(jac, 3)
    assert np.all(np.isnan(basis[1]))
    np.testing.assert_allclose(basis[0].T @ jac[0], 0.0, atol=1e-15)
    np.testing.assert_allclose(basis[0].T @ basis[0], np.eye(3), atol=1e-15)


def test_the_shipped_stage_is_the_generators() -> None:
    """examples/flexure_3rrr.toml is what scripts/chain_examples.py writes (its header
    states every value and source)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "chain_examples", ROOT / "scripts" / "chain_examples.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    shipped = ROOT / "examples" / "flexure_3rrr.toml"
    assert shipped.read_text(encoding="utf-8") == module.flexure_3rrr()


def test_hinges_without_a_yield_strength_have_no_range(
    tmp_path: Path, stage_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Without a yield strength (optional in a hinge's material) ``analyze`` runs and
    prints no hinge table; ``--safety-factor`` is then refused, naming the key."""
    from ppm_stiffness.cli import main

    text = stage_path.read_text(encoding="utf-8")
    path = tmp_path / "no_yield.toml"
    path.write_text(text.replace(", yield_strength = 5.03e+08", ""), encoding="utf-8")
    assert "yield_strength" not in path.read_text(encoding="utf-8").split("[[legs]]")[1]
    assert main(["analyze", "--design", str(path)]) == 0
    assert "Range of motion" not in capsys.readouterr().out
    assert main(["analyze", "--design", str(path), "--safety-factor", "2"]) == 2
    assert "has no yield_strength" in capsys.readouterr().err
