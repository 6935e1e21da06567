"""The joint-kind records (:mod:`ppm_stiffness.legs.joint_kinds`): their facts checked
against physical properties and the FE frame, every kind drawn, and no module outside
the records (and the leg types, which write joint lists) testing a joint's letter."""

from __future__ import annotations

import ast
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from ppm_stiffness.core.errors import DesignError  # noqa: E402
from ppm_stiffness.legs.chain import Joint, constrained_screws, freedom_screws  # noqa: E402
from ppm_stiffness.legs.joint_kinds import JOINT_KINDS, joint_kind  # noqa: E402
from ppm_stiffness.validation.joints import joint_stiffness  # noqa: E402
from ppm_stiffness.visuals import mechanism  # noqa: E402
from ppm_stiffness.visuals.leg_geometry import JointView  # noqa: E402

SRC = Path(__file__).parents[1] / "src" / "ppm_stiffness"
KINDS = sorted(JOINT_KINDS)
#: The six directions of a joint frame: rotations about and translations along e1-e3.
ALL_DIRECTIONS = sorted((d, k) for d in "rt" for k in range(3))
#: The FE frame's numbering of a joint's relative motions (validation/joints.py's doc):
#: 0-2 rotations about e1, e2, e3; 3-5 translations along e1, e2, e3.
MOTION = {"r": 0, "t": 3}
#: Modules that may name joint letters: the records, and the leg types / presets that
#: write joint lists (data, not branches).
ALLOWED = ("legs/joint_kinds.py", "legs/types/", "legs/presets/")


def random_joint(kind: str, seed: int, turn: float = 0.0) -> Joint:
    """A joint of ``kind`` at a random point with random perpendicular axes; ``turn``
    [rad] turns its second axis about the first."""
    rng = np.random.default_rng(seed)
    e1 = rng.normal(size=3)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(e1, rng.normal(size=3))
    e2 /= np.linalg.norm(e2)
    e2 = np.cos(turn) * e2 + np.sin(turn) * np.cross(e1, e2)
    return Joint(kind, e1, rng.normal(size=3), axis2=e2)  # type: ignore[arg-type]


@pytest.mark.parametrize("kind", KINDS)
def test_freedoms_and_constraints_share_the_six_directions_once(kind: str) -> None:
    """A joint's freedoms and its constrained directions split the six relative motions:
    each direction is one or the other, exactly once."""
    record = joint_kind(kind)
    assert sorted(record.freedoms + record.constrained) == ALL_DIRECTIONS
    assert record.freedom_count + record.constrained_count == 6


@pytest.mark.parametrize("kind", KINDS)
def test_freedom_and_constraint_twists_span_all_twists(kind: str) -> None:
    """At a random point and axes, the joint's freedom twists and constrained twists are
    independent and together span every twist (rank 6)."""
    joint = random_joint(kind, seed=3)
    free, fixed = freedom_screws(joint), constrained_screws(joint)
    record = joint_kind(kind)
    assert free.shape == (6, record.freedom_count)
    assert fixed.shape == (6, record.constrained_count)
    assert np.linalg.matrix_rank(np.hstack([free, fixed]), tol=1e-12) == 6


@pytest.mark.parametrize("kind", KINDS)
def test_second_axis_exactly_where_the_freedoms_depend_on_it(kind: str) -> None:
    """A kind needs its second axis (``second_axis``) iff turning e2 about e1 changes the
    span of its freedom twists (a U: yes; R, P, C about or along e1 alone, and S's three
    rotations: no)."""
    a = freedom_screws(random_joint(kind, seed=5))
    b = freedom_screws(random_joint(kind, seed=5, turn=0.7))
    same_span = np.linalg.matrix_rank(np.hstack([a, b]), tol=1e-12) == a.shape[1]
    assert joint_kind(kind).second_axis == (not same_span)


@pytest.mark.parametrize("kind", KINDS)
def test_fe_releases_are_the_freedoms(kind: str) -> None:
    """The FE joint releases exactly the kind's freedoms (in order, the actuated one
    first); its springs land on the constrained directions in spring order."""
    record = joint_kind(kind)
    assert record.fe_releases == tuple(MOTION[d] + k for d, k in record.freedoms)
    joint = random_joint(kind, seed=7)
    rigid = joint_stiffness(joint, 9.0)
    free = np.zeros(6, dtype=bool)
    free[list(record.fe_releases)] = True
    assert np.all(rigid[free] == 0.0) and np.all(np.isinf(rigid[~free]))
    springs = np.arange(1.0, record.constrained_count + 1.0)
    sprung = Joint(kind, joint.axis, joint.point, springs, axis2=joint.axis2)  # type: ignore[arg-type]
    k = joint_stiffness(sprung, 9.0)
    motions = [MOTION[d] + i for d, i in record.constrained]
    np.testing.assert_array_equal(k[motions], springs)


@pytest.mark.parametrize("kind", [k for k in KINDS if joint_kind(k).freedom_count == 1])
def test_actuated_freedom_units_follow_its_motion(kind: str) -> None:
    """An actuator along a rotation is rotary (N·m, rad, N·m/rad), along a translation
    linear (N, m, N/m); the FE frame puts its stiffness on that motion."""
    record = joint_kind(kind)
    rotary = record.freedoms[0][0] == "r"
    assert record.actuator_units() == (("N·m", "rad", "N·m/rad") if rotary else ("N", "m", "N/m"))
    assert record.linear == (not rotary)
    joint = random_joint(kind, seed=9)
    actuated = Joint(kind, joint.axis, joint.point, actuated=True)  # type: ignore[arg-type]
    k = joint_stiffness(actuated, 9.0)
    assert k[0 if rotary else 3] == 9.0


def test_an_unknown_kind_is_refused_by_name() -> None:
    with pytest.raises(DesignError, match=r"unknown joint kind 'X': valid kinds are R, P, C"):
        joint_kind("X")


def test_symbols_and_words_tell_the_kinds_apart() -> None:
    """Each kind's symbol (marker, fill) is its own, and its words name it."""
    records = list(JOINT_KINDS.values())
    assert len({(r.marker, r.filled) for r in records}) == len(records)
    for r in records:
        assert r.name in r.legend and r.letter in r.legend, r
        assert r.name in r.caption and r.letter in r.caption, r
        assert r.label == f"{r.name} joint {r.letter}"
        assert (r.bar is None) == r.spherical, r  # a ball has no axis to draw


@pytest.mark.parametrize("kind", KINDS)
def test_the_top_view_draws_every_kind(kind: str) -> None:
    """The planar picture draws any joint kind with its record's symbol (it raised
    KeyError for U and S)."""
    record = joint_kind(kind)
    view = JointView(
        kind=kind,
        point=np.array([0.01, 0.02, 0.0]),
        axis=np.array([1.0, 0.0, 0.0]),
        axis2=np.array([0.0, 1.0, 0.0]) if record.second_axis else None,
        actuated=False,
        name="j",
    )
    fig, ax = plt.subplots()
    mechanism._draw_joint(ax, view, 1, 1, "tab:red", 10.0, lambda label: label)
    symbol = next(c for c in ax.collections if c.get_gid() == "joint-1-1")
    assert symbol.get_label() == record.label
    assert symbol.get_sizes()[0] == record.size_2d
    bars = [line for line in ax.lines]
    assert len(bars) == (1 if record.slides else 0)
    plt.close(fig)


# --- architecture: no joint-letter branch outside the records ----------------------


def _letters(node: ast.AST) -> bool:
    """A joint letter, or a tuple / list / set of them."""
    if isinstance(node, ast.Constant):
        return node.value in JOINT_KINDS
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return bool(node.elts) and all(_letters(e) for e in node.elts)
    return False


def letter_branches(source: str) -> list[int]:
    """Lines of ``source`` that test a joint's letter: a comparison of something named
    ``kind`` (``joint.kind``, ``ACTUATED_KIND``) with a letter or letters, or a table
    keyed by joint letters (a dict literal of two or more letter keys)."""
    lines = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Compare):
            operands = [node.left, *node.comparators]
            if any(_letters(o) for o in operands) and any(
                "kind" in ast.unparse(o).lower() for o in operands if not _letters(o)
            ):
                lines.append(node.lineno)
        elif isinstance(node, ast.Dict):
            keys = [k for k in node.keys if k is not None]
            if len(keys) >= 2 and all(_letters(k) for k in keys):
                lines.append(node.lineno)
    return lines


@pytest.mark.parametrize(
    ("snippet", "flagged"),
    [
        ('if joint.kind == "U":\n    pass', True),
        ('ok = element.kind not in ("R", "P", "C")', True),
        ('unit = "rad" if self.ACTUATED_KIND == "R" else "m"', True),
        ('SIZES = {"R": 45, "P": 70}', True),
        ('where = "P" if point == "P" else "T"', False),
        ('at = "T" if tool else "P"', False),
        ('ok = kind == "r"', False),
    ],
)
def test_the_letter_check_finds_branches(snippet: str, flagged: bool) -> None:
    """The architecture check below flags a joint-letter branch or table (so that it
    fails when one is added) and not the platform point P or a direction's "r"."""
    assert bool(letter_branches(snippet)) == flagged


def test_no_module_outside_the_records_tests_a_joint_letter() -> None:
    """Joint-kind knowledge lives in the records only: no other module of the package
    compares a kind with a letter or keeps a table keyed by letters."""
    found = []
    for path in sorted(SRC.rglob("*.py")):
        rel = path.relative_to(SRC).as_posix()
        if rel.startswith(ALLOWED[1:]) or rel == ALLOWED[0]:
            continue
        found += [f"{rel}:{n}" for n in letter_branches(path.read_text(encoding="utf-8"))]
    assert not found, found
