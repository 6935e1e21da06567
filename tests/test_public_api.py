"""The public API (issue 27, item 14): every result type importable from the package,
typed results for ``analyze`` and ``modal_analysis`` whose ``to_dict()`` is the
``--json`` document, one name per concept with the names of 0.2 deprecated, and the
batched K."""

from __future__ import annotations

import dataclasses
import inspect
import json
import re
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pytest

import ppm_stiffness as pps
from helpers import within_required
from ppm_stiffness.analysis import ENVELOPE_KEYS, dump_json
from ppm_stiffness.cli import main
from ppm_stiffness.core.conventions import length_balanced
from ppm_stiffness.poses import task_values

if TYPE_CHECKING:
    from helpers import DocRun

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = sorted((ROOT / "examples").glob("*.toml"))
PAPER_WRENCH = np.array([0.0, 0.0, 0.1, 5.0, 5.0, 20.0])

#: Names in return annotations that are not result types of the package.
NOT_RESULTS = {"FloatArray", "BoolArray", "None", "tuple", "list", "dict", "str", "Any"}


def _returned_types() -> set[str]:
    """The class names in the return annotations of the public functions."""
    names: set[str] = set()
    for name in pps.__all__:
        obj = getattr(pps, name)
        if inspect.isfunction(obj):
            annotation = str(inspect.signature(obj).return_annotation)
            names |= set(re.findall(r"[A-Za-z_]\w*", annotation)) - NOT_RESULTS
    return names


def test_every_result_type_is_exported() -> None:
    """A function of ``__all__`` returns only arrays or classes of ``__all__``, each
    importable from the package (12 of them were not in 0.2)."""
    returned = _returned_types()
    assert {"ScrewSprings", "Decoupling", "LoadedState", "MovingLoadedState"} <= returned
    assert returned <= set(pps.__all__), returned - set(pps.__all__)
    for name in returned | {"Analysis", "ModalAnalysis", "MatrixAnalysis", "MarginKind"}:
        namespace: dict[str, object] = {}
        exec(f"from ppm_stiffness import {name}", namespace)
        assert inspect.isclass(namespace[name]), name
        assert name in pps.__all__


def test_analyze_and_modal_analysis_are_typed() -> None:
    design = pps.load_design(ROOT / "examples" / "hexapod_6ups.toml")
    result = pps.analyze(design, wrench=PAPER_WRENCH)
    assert isinstance(result, pps.Analysis) and dataclasses.is_dataclass(result)
    assert isinstance(result.decoupling, pps.Decoupling)
    assert isinstance(result.eigenscrews, pps.ScrewSprings)
    assert isinstance(result.principal_compliance, pps.PrincipalCompliance)
    assert result.pose.shape == (6,) and result.twist is not None
    # the analysis's K is the loaded state's, moved to the tool point (P here)
    state = pps.loaded_state(design, PAPER_WRENCH)
    assert np.array_equal(result.stiffness_matrix, state.stiffness_matrix)
    assert np.array_equal(result.twist, state.twist)
    modal = pps.modal_analysis(design)
    assert isinstance(modal, pps.ModalAnalysis) and isinstance(modal.modes, pps.Modes)
    assert modal.frequencies[0] == result.first_frequency or result.first_frequency is None


def _cli_json(capsys: pytest.CaptureFixture[str], *argv: str) -> str:
    assert main(list(argv)) == 0
    return capsys.readouterr().out


CASES = {
    "built-in": ([], {}),
    "built-in, loaded, at a tool point": (
        ["--wrench", "5,5,20,0,0,0.1", "--tool-point", "10,0,5", "--x", "2", "--phi", "3"],
        {
            "pose": [0.002, 0.0, np.radians(3.0)],
            "wrench": [0.0, 0.0, 0.1, 5.0, 5.0, 20.0],
            "tool_point": [0.01, 0.0, 0.005],
        },
    ),
    "built-in, moving geometry": (
        ["--wrench", "5,5,20,0,0,0.1", "--geometry", "moving"],
        {"wrench": [0.0, 0.0, 0.1, 5.0, 5.0, 20.0], "geometry": "moving"},
    ),
    "hexapod, loaded": (
        ["--design", "examples/hexapod_6ups.toml", "--wrench", "5,5,20,0,0,0.1"],
        {"design": "examples/hexapod_6ups.toml", "wrench": [0.0, 0.0, 0.1, 5.0, 5.0, 20.0]},
    ),
    "3-PRS, least squares": (
        ["--design", "examples/3prs.toml", "--method", "least-squares"],
        {"design": "examples/3prs.toml", "method": "least-squares"},
    ),
}


@pytest.mark.parametrize("case", CASES)
def test_to_dict_is_the_cli_json(
    case: str, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """``to_json()`` is byte for byte what ``analyze --json`` prints, and ``to_dict()``
    its keys after the envelope, in order."""
    monkeypatch.chdir(ROOT)
    argv, kwargs = CASES[case]
    out = _cli_json(capsys, "analyze", "--json", *argv)
    kwargs = dict(kwargs)
    path = kwargs.pop("design", None)
    design = pps.default_design() if path is None else pps.load_design(str(path))
    result = pps.analyze(design, **kwargs)  # type: ignore[arg-type]
    assert result.to_json() + "\n" == out
    document = json.loads(out)
    for key in ENVELOPE_KEYS:
        document.pop(key)
    as_dict = json.loads(dump_json(result.to_dict()))
    assert list(as_dict) == list(document) and as_dict == document


@pytest.mark.parametrize("name", ["hexapod_6ups", "3prs"])
def test_modal_to_dict_is_the_cli_json(
    name: str, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(ROOT)
    path = f"examples/{name}.toml"
    out = _cli_json(capsys, "modes", "--json", "--design", path, "--wrench", "5,5,20,0,0,0.1")
    result = pps.modal_analysis(pps.load_design(path), wrench=PAPER_WRENCH)
    assert result.to_json() + "\n" == out
    document = json.loads(out)
    assert json.loads(dump_json(result.to_dict())) == {
        k: v for k, v in document.items() if k not in ENVELOPE_KEYS
    }


def test_mapping_access_warns_and_gives_the_old_values() -> None:
    result = pps.analyze(pps.default_design())
    old = result.to_dict()
    with pytest.warns(
        DeprecationWarning, match=r"result\['principal'\] \(mapping access on "
    ) as record:
        assert result["principal"] == old["principal"]
    assert record[0].filename == __file__  # points at the caller's line
    with pytest.warns(DeprecationWarning, match="use its attributes, or .to_dict"):
        assert ("twist" in result) is False
    with pytest.warns(DeprecationWarning, match=r"result.get\('first_frequency'\)"):
        assert result.get("first_frequency") == old["first_frequency"]
    with pytest.warns(DeprecationWarning, match="removed in 0.4"):
        assert list(result.keys()) == list(old)
    with pytest.warns(DeprecationWarning, match="iterating over result"):
        assert list(result) == list(old)
    modal = pps.modal_analysis(pps.default_design())
    with pytest.warns(DeprecationWarning, match=r"mapping access on ModalAnalysis"):
        assert modal["frequencies"] == modal.frequencies.tolist()


def test_old_names_warn_and_still_work() -> None:
    design = pps.default_design()
    with pytest.warns(
        DeprecationWarning,
        match=r"ppm_stiffness.equilibrium is deprecated "
        r"since 0.3: use ppm_stiffness.loaded_state",
    ) as record:
        old = pps.equilibrium(design, PAPER_WRENCH, pps.home_pose(design))
    assert record[0].filename == __file__
    assert np.array_equal(old.twist, pps.loaded_state(design, PAPER_WRENCH).twist)
    with pytest.warns(DeprecationWarning, match="use ppm_stiffness.moving_loaded_state"):
        from ppm_stiffness import moving_equilibrium  # noqa: PLC0415
    assert moving_equilibrium is pps.moving_loaded_state
    with pytest.warns(DeprecationWarning, match="use ppm_stiffness.MovingLoadedState"):
        assert pps.MovingEquilibrium is pps.MovingLoadedState
    assert not {"equilibrium", "moving_equilibrium", "MovingEquilibrium"} & set(pps.__all__)


def _poses(design: pps.Design) -> np.ndarray:
    """Five task-coordinate poses near home (1 mm, 0.5 deg; within a flexure stage's
    required region) and one 10 m away."""
    home = task_values(design, pps.home_pose(design))
    scale = np.array(
        [1e-3 if c in ("x", "y", "z") else np.radians(0.5) for c in design.task_coordinates]
    )
    scale = within_required(design, scale)
    near = home + np.random.default_rng(27).uniform(-1.0, 1.0, (5, home.size)) * scale
    far = home.copy()
    lengths = [c in ("x", "y", "z") for c in design.task_coordinates]
    if any(lengths):
        far[lengths.index(True)] += 10.0
    else:  # a wrist: a turn beyond its drives' strokes
        far[0] += 2.0
    return np.vstack([near, far])


@pytest.mark.parametrize(
    "path", EXAMPLES + [None], ids=lambda p: "built-in" if p is None else p.stem
)
def test_batched_stiffness_matrix_is_the_single_pose_one(path: Path | None) -> None:
    """``stiffness_matrix(design, poses)`` equals ``stiffness_at_pose`` pose by pose
    (largest difference 5.7e-14 of the largest length-balanced entry, on the P-P-R
    designs' reduced path); where that raises (a pose 10 m away) the batched call
    raises the same error, or gives NaN when asked to mask."""
    design = pps.default_design() if path is None else pps.load_design(path)
    poses = _poses(design)
    with pytest.raises(pps.UnreachablePoseError, match=r"1 outside the joint limits of 6 poses"):
        pps.stiffness_matrix(design, poses)
    k = pps.stiffness_matrix(design, poses, refused="nan")
    assert k.shape == (6, 6, 6)
    for i in range(5):
        single = length_balanced(pps.stiffness_at_pose(design, poses[i]))
        diff = np.max(np.abs(length_balanced(k[i]) - single)) / np.max(np.abs(single))
        assert diff < 3e-13, (i, diff)
    with pytest.raises(pps.UnreachablePoseError):
        pps.stiffness_at_pose(design, poses[5])
    assert np.all(np.isnan(k[5]))
    full = np.array([pps.full_pose(design, p) for p in poses[:4]]).reshape(2, 2, 6)
    assert np.array_equal(pps.stiffness_matrix(design, full).reshape(4, 6, 6), k[:4])


def test_api_page_uses_no_deprecated_name(doc_runs: dict[str, DocRun]) -> None:
    """Every code block of docs/api.md and the README runs without a DeprecationWarning
    of the package (the library calls itself by the new names; the blocks are run once
    per session, tests/conftest.py)."""
    assert sum(run.blocks for run in doc_runs.values()) >= 7
    assert {page: run.error for page, run in doc_runs.items()} == dict.fromkeys(doc_runs)


def test_batched_stiffness_matrix_is_nan_at_a_singular_pose() -> None:
    """At (0, 0, -60.05 deg) the 3-RPR's leg lines nearly meet at P (test_singularity):
    the single-pose K raises, so does the batched one; masked, it is NaN there and K
    elsewhere."""
    design = pps.load_design(ROOT / "examples" / "3rpr.toml")
    poses = np.array([[0.0, 0.0, np.radians(-60.05)], [0.0, 0.0, 0.0]])
    with pytest.raises(pps.SingularConfigurationError, match="transmission index"):
        pps.stiffness_at_pose(design, poses[0])
    with pytest.raises(pps.SingularConfigurationError, match=r"1 singular of 2 poses"):
        pps.stiffness_matrix(design, poses)
    with pytest.raises(pps.InputDataError, match="give 'raise' or 'nan'"):
        pps.stiffness_matrix(design, poses, refused="mask")
    k = pps.stiffness_matrix(design, poses, refused="nan")
    assert np.all(np.isnan(k[0]))
    single = pps.stiffness_at_pose(design, poses[1])
    assert np.max(np.abs(k[1] - single)) <= 3e-13 * np.max(np.abs(single))


def test_batched_mass_matrix_is_nan_where_a_leg_cannot_reach() -> None:
    """The hexapod 5 m off home: ``mass_matrix_at_pose`` raises, and the batched M is
    NaN there (it was a finite M_zz of 3.16 kg), the single-pose M at home (to
    round-off: measured 0 to 1e-16 relative)."""
    design = pps.load_design(ROOT / "examples" / "hexapod_6ups.toml")
    home = pps.home_pose(design)
    poses = home + np.array([[0.0] * 6, [5.0, 0, 0, 0, 0, 0]])
    with pytest.raises(pps.UnreachablePoseError, match="reach|outside"):
        pps.mass_matrix_at_pose(design, poses[1])
    m = pps.mass_matrix(design, poses)
    assert np.all(np.isnan(m[1]))
    single = pps.mass_matrix_at_pose(design, poses[0])
    assert np.max(np.abs(m[0] - single)) <= 1e-15 * np.max(np.abs(single))
