"""``map --actuators WRENCH --geometry moving`` and the ``load_margin`` map quantity.

Point by point the map's values are the single-pose analysis with moving geometry
(``analyze_design(..., geometry="moving")``: the paper's and the spatial principal
stiffnesses of K_F's symmetric part at the displaced tool point, and the load margin),
to 1e-10 relative; the map masks exactly where ``moving_equilibrium`` raises, with the
reason code of its refusal.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from tests.helpers import design_named
from tests.paper import PAPER_WRENCH

from ppm_stiffness.analysis import analyze_design
from ppm_stiffness.cli import main
from ppm_stiffness.core.decoupling import decouple
from ppm_stiffness.core.errors import EquilibriumError, InputDataError
from ppm_stiffness.core.principal import principal_compliance
from ppm_stiffness.core.refusals import Refusal
from ppm_stiffness.maps.map_chunks import quantity_names
from ppm_stiffness.maps.result import PRINCIPAL, load_npz
from ppm_stiffness.maps.workspace import stiffness_map
from ppm_stiffness.statics.margin import MAX_FACTOR, MarginKind, load_margin
from ppm_stiffness.statics.moving import moving_equilibrium

RTOL = 1e-10
#: rx, ry bounds of the 3-PRS slice [rad]
BOUNDS = (-0.1, 0.1, -0.08, 0.08)
ROOT = Path(__file__).parents[1]


def _task(design, smap, i: int, j: int) -> np.ndarray:  # type: ignore[no-untyped-def]
    values = dict(smap.fixed) | {smap.axes[0]: smap.u[i], smap.axes[1]: smap.v[j]}
    return np.array([values[name] for name in design.task_coordinates])


def _margin_value(design, wrench, pose, tool) -> float:  # type: ignore[no-untyped-def]
    m = load_margin(design, wrench, pose, tool)
    if m.factor is not None:
        return m.factor
    return m.searched_up_to if m.kind == MarginKind.STROKE else MAX_FACTOR


def test_planar_moving_map_is_the_single_pose_analysis_and_masks_its_refusals() -> None:
    # 3.262 times the paper's load: the load margins over the slice are 3.254-3.272,
    # so the map has poses past the limit point (no equilibrium) and poses before it
    design = design_named("paper")
    wrench = 3.262 * PAPER_WRENCH
    smap = stiffness_map(
        design,
        actuators="wrench",
        wrench=wrench,
        grid=(3, 2),
        geometry="moving",
        quantities="paper,load-margin",
    )
    assert smap.geometry == "moving"
    assert 0 < smap.reachable.sum() < smap.reachable.size
    assert set(smap.refusal_counts()) == {Refusal.NO_EQUILIBRIUM.reason}
    for j in range(smap.v.size):
        for i in range(smap.u.size):
            pose = _task(design, smap, i, j)
            if not smap.reachable[j, i]:
                with pytest.raises(EquilibriumError, match="no equilibrium"):
                    moving_equilibrium(design, wrench, pose)
                assert smap.refusal is not None
                assert smap.refusal[j, i] == Refusal.NO_EQUILIBRIUM
                continue
            k_f = moving_equilibrium(design, wrench, pose).stiffness_matrix
            dec = decouple(0.5 * (k_f + k_f.T), "paper")
            ref = [dec.rotational_values[2], *dec.translational_values[:2]]
            got = [smap.quantities[q][j, i] for q in ("k_phi", "k_x", "k_y")]
            np.testing.assert_allclose(got, ref, rtol=RTOL)
            lam = smap.quantities["load_margin"][j, i]
            assert lam == pytest.approx(_margin_value(design, wrench, pose, None), rel=RTOL)
            assert 1.0 <= lam < 1.01  # the path is stable up to the load, not much further
    # one pose through the whole single-pose analysis (analyze --geometry moving)
    j, i = np.argwhere(smap.reachable)[0]
    doc = analyze_design(design, _task(design, smap, i, j), wrench, geometry="moving").to_dict()
    rot = doc["principal"]["rotational"]["values"][2]
    assert smap.quantities["k_phi"][j, i] == pytest.approx(rot, rel=RTOL)
    factor = doc["moving_geometry"]["load_margin"]["factor"]
    assert smap.quantities["load_margin"][j, i] == pytest.approx(factor, rel=RTOL)


def test_spatial_moving_map_at_a_tool_point_is_the_single_pose_analysis() -> None:
    # the 3-PRS's tool point is 150 mm below P: the wrench acts there and K_F is there
    design = design_named("3prs")
    w_tool = np.array([1.0, -2.0, 0.5, 300.0, -100.0, -2000.0])
    tool = np.asarray(design.tool_point)
    smap = stiffness_map(
        design,
        axes=("rx", "ry"),
        grid=(3, 2),
        bounds=BOUNDS,
        actuators="wrench",
        wrench=w_tool,
        geometry="moving",
        quantities="principal,load_margin",
    )
    assert smap.reachable.all()
    for j, i in np.argwhere(smap.reachable):
        pose = _task(design, smap, i, j)
        k_f = moving_equilibrium(design, w_tool, pose, tool).stiffness_matrix
        pc = principal_compliance(0.5 * (k_f + k_f.T))
        ref = np.concatenate([np.sort(pc.rotational_values), np.sort(pc.translational_values)])
        got = np.array([smap.quantities[q][j, i] for q in PRINCIPAL])
        np.testing.assert_allclose(got, ref, rtol=RTOL)
        lam = smap.quantities["load_margin"][j, i]
        assert lam == pytest.approx(_margin_value(design, w_tool, pose, tool), rel=RTOL)
    # not the frozen map: 2 kN at 150 mm below P moves translational_min by 4.5-5.0 %
    frozen = stiffness_map(
        design, axes=("rx", "ry"), grid=(3, 2), bounds=BOUNDS, actuators="wrench", wrench=w_tool
    )
    ok = smap.reachable & frozen.reachable
    a = smap.quantities["translational_min"][ok]
    b = frozen.quantities["translational_min"][ok]
    assert np.min(np.abs(a / b - 1)) > 0.04


def test_load_margin_needs_a_wrench_and_moving_needs_one_too() -> None:
    design = design_named("paper")
    with pytest.raises(InputDataError, match="need a wrench"):
        stiffness_map(design, grid=3, quantities="paper,load_margin")
    with pytest.raises(InputDataError, match="need a wrench"):
        stiffness_map(design, grid=3, geometry="moving")
    assert quantity_names(design, "paper,load-margin") == ("k_phi", "k_x", "k_y", "load_margin")
    assert quantity_names(design, "load-margin") == ("load_margin",)
    with pytest.raises(InputDataError, match="unknown map quantity"):
        quantity_names(design, "paper,margin")


def test_cli_moving_map_json_npz_and_csv(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    jsonschema = pytest.importorskip("jsonschema")
    npz, csv = tmp_path / "m.npz", tmp_path / "m.csv"
    argv = ["map", "--grid", "3", "--actuators", "5,5,20,0,0,0.1", "--geometry", "moving"]
    argv += ["--quantities", "paper,load-margin", "--json", "--data", str(npz)]
    assert main(argv) == 0
    doc = json.loads(capsys.readouterr().out)
    schema = json.loads((ROOT / "docs/schemas/map.schema.json").read_text(encoding="utf-8"))
    jsonschema.validate(doc, schema, cls=jsonschema.Draft202012Validator)
    assert doc["geometry"] == "moving" and doc["quantities"]["load_margin"] == "1"
    smap = load_npz(npz)
    assert smap.geometry == "moving"
    assert smap.summary()["load_margin"]["min"] == pytest.approx(3.25, abs=0.02)
    assert main([*argv[:-2], "--data", str(csv)]) == 0
    capsys.readouterr()
    text = csv.read_text(encoding="utf-8")
    assert "# geometry: moving" in text and "load_margin_factor" in text
    assert main(["map", "--grid", "3", "--geometry", "moving"]) == 2
    assert "need a wrench" in capsys.readouterr().err


def test_spatial_masks_carry_the_single_pose_refusal() -> None:
    # 50 kN down on the 3-RPS: past its sideways buckling (load margin 1.52 of 20 kN at
    # home, a bifurcation): some poses' paths are found unstable (UNSTABLE), others stop
    # (NO_EQUILIBRIUM); each pose's code is the error moving_equilibrium raises there
    design = design_named("3rps")
    wrench = np.array([0.0, 0.0, 0.0, 0.0, 0.0, -5e4])
    smap = stiffness_map(
        design,
        axes=("rx", "ry"),
        grid=(2, 2),
        bounds=(-0.05, 0.05, -0.05, 0.05),
        actuators="wrench",
        wrench=wrench,
        geometry="moving",
    )
    assert smap.refusal is not None
    assert set(smap.refusal.ravel()) == {Refusal.NO_EQUILIBRIUM, Refusal.UNSTABLE}
    messages = {
        Refusal.NO_EQUILIBRIUM: "no equilibrium with moving geometry",
        Refusal.UNSTABLE: "beyond the first instability",
    }
    for j in range(2):
        for i in range(2):
            with pytest.raises(EquilibriumError, match=messages[Refusal(smap.refusal[j, i])]):
                moving_equilibrium(design, wrench, _task(design, smap, i, j))


def test_a_margin_at_the_end_of_the_search_is_named_as_such(capsys) -> None:
    """The table's load_margin 1e3 is MAX_FACTOR, the end of the search, not a measured
    margin: the text says at how many poses no instability was found (a 3-PRS under a
    load it carries far beyond 1000 times)."""
    from ppm_stiffness.statics.margin import MAX_FACTOR

    argv = ["map", "--design", str(ROOT / "examples" / "3prs.toml"), "--axes", "rx,ry"]
    argv += ["--z", "380", "--actuators", "100,0,-500,0,0,0", "--grid", "3"]
    assert main([*argv, "--quantities", "principal,load-margin"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    assert f"load_margin {MAX_FACTOR:g} is the end of the search" in out
    assert "times the wrench at" in out
