"""Implausible link bodies and masses (issue 27, items 1 and 2): a centre of mass
outside the leg is refused and one outside its link warned, in a design file and in
`optimize --vary` ranges; a link mass in grams (its density against its section), a
rotor reflecting tonnes onto its coordinate and a platform lighter than a milligram are
refused naming the check and the likely value. Library and CLI (one line, exit 2)."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import pytest

from ppm_stiffness.cli import main
from ppm_stiffness.core.errors import DesignError, ImplausibleDesignWarning
from ppm_stiffness.design import default_design, load_design

ROOT = Path(__file__).parents[1]
HEXAPOD = ROOT / "examples" / "hexapod_6ups.toml"
RRR = ROOT / "examples" / "3rrr.toml"


def _edited(tmp_path: Path, source: Path, old: str, new: str) -> Path:
    """``source`` with its first ``old`` replaced by ``new``, written to tmp_path."""
    text = source.read_text(encoding="utf-8")
    assert old in text
    path = tmp_path / source.name
    path.write_text(text.replace(old, new, 1), encoding="utf-8")
    return path


def _cli_refuses(argv: list[str], capsys: pytest.CaptureFixture[str], pattern: str) -> None:
    """One line on stderr matching ``pattern``, exit 2, nothing on stdout."""
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert len(err.strip().splitlines()) == 1, err
    assert re.search(pattern, err), err


#: A rod's centre 10 m from its platform end (a rod of 0.125 m at most, a leg of
#: 0.265 m at most): it was accepted and dropped the hexapod's f1 from 245 to 7.4 Hz.
ROD_CENTRE_10M = ("mass_centre = 0.1228", "mass_centre = 10.0")
CENTRE_REFUSED = (
    r"rod\.mass_centre = 10: the link's centre of mass would lie outside the leg, whose "
    r"longest length over its stroke is 0\.265 m \(0 <= mass_centre <= 0\.265 m\); did "
    r"you mean 0\.01 \(mm\)\?"
)


def test_a_centre_outside_the_leg_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _edited(tmp_path, HEXAPOD, *ROD_CENTRE_10M)
    with pytest.raises(DesignError, match=CENTRE_REFUSED):
        load_design(path)
    _cli_refuses(["modes", "--design", str(path)], capsys, CENTRE_REFUSED)


def test_a_centre_past_its_link_is_warned_and_used(tmp_path: Path) -> None:
    """The 3-RRR's distal link is 0.15 m: a centre 0.2 m from its start is past its end
    (within the leg, 0.3 m): warned, and the design loads."""
    path = _edited(tmp_path, RRR, "mass_centre = 0.04749", "mass_centre = 0.2")
    with pytest.warns(ImplausibleDesignWarning, match=r"distal\.mass_centre beyond 0\.15 m"):
        design = load_design(path)
    assert design.legs[0].distal.mass_centre == 0.2


def test_the_shipped_designs_are_not_warned() -> None:
    """The rods fixed to their platform end have their centres behind their guides
    (inside the cylinder or bearing): that is where they are, not warned."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", ImplausibleDesignWarning)
        default_design()
        for path in sorted((ROOT / "examples").glob("*.toml")):
            load_design(path)


def test_an_optimize_range_reaching_outside_the_leg_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "best.toml"
    argv = ["optimize", "--design", str(HEXAPOD), "--out", str(out), "--budget", "10"]
    _cli_refuses(
        [*argv, "--vary", "leg*.rod.mass_centre=0.05:0.5"],
        capsys,
        r"--vary leg\*\.rod\.mass_centre: HI = 0\.5 m is refused by the design .*"
        r"rod\.mass_centre = 0\.5: the link's centre of mass would lie outside the leg",
    )
    assert not out.exists()


def test_a_length_range_that_puts_a_centre_outside_the_leg_is_refused(tmp_path: Path) -> None:
    """A 3-RRR leg is proximal_length + 0.15 m long at most: with the distal centre 0.2 m
    from its start, a proximal length down to 0.01 m puts it outside the leg."""
    path = _edited(tmp_path, RRR, "mass_centre = 0.04749", "mass_centre = 0.2")
    with pytest.warns(ImplausibleDesignWarning, match=r"\.mass_centre beyond [0-9.]+ m puts"):
        design = load_design(path)
        design.check_range("leg*.proximal_length", 0.1, 0.2)  # 0.25 m and more: fine
        refused = (
            r"range \[0\.01, 0\.2\] of leg\*\.proximal_length = 0\.01: distal\.mass_centre "
            r"= 0\.2: the link's centre of mass would lie outside the leg, whose longest "
            r"length over its stroke is 0\.16 m \(0 <= mass_centre <= 0\.16 m\)$"
        )
        with pytest.raises(DesignError, match=refused):
            design.check_range("leg*.proximal_length", 0.01, 0.2)


# -- item 2: masses -------------------------------------------------------------------


def test_a_link_mass_in_grams_is_refused_by_its_density(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """244.2 (g) for the hexapod's 0.2442 kg rod: 1.73e7 kg/m^3 on its section
    (1.131e-4 m^2) over its longest free length (0.125 m); below the 1e4 kg limit of a
    body, so only the density names it."""
    path = _edited(tmp_path, HEXAPOD, "mass = 0.2442", "mass = 244.2")
    pattern = (
        r"rod\.mass = 244\.2: implausible density: a link of section 0\.000113 m\^2 and "
        r"0\.125 m \(its longest\) would be 1\.73e\+07 kg/m\^3, above 250000 .*did you "
        r"mean 0\.2442 \(g\)\?"
    )
    with pytest.raises(DesignError, match=pattern):
        load_design(path)
    _cli_refuses(["analyze", "--design", str(path)], capsys, pattern)


def test_a_rotor_reflecting_tonnes_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """0.5 kg·m^2 (a catalogue's 0.5 kg·cm^2 typed as is) through 4500 rad/m reflects
    1.01e7 kg onto the strut; 5e-5 kg·m^2 reflects 1013 kg (accepted: a big motor on a
    fine screw)."""
    drive = "threshold_displacement = 0.0\nrotor_inertia = {}\ngear_ratio = 4500.0\n"
    old = "threshold_displacement = 0.0\n"
    path = _edited(tmp_path, HEXAPOD, old, drive.format(0.5))
    pattern = (
        r"actuator\.gear_ratio = 4500 with actuator\.rotor_inertia = 0\.5: implausible "
        r"reflected inertia, rotor_inertia \* gear_ratio\^2 = 1\.01e\+07 kg .*\(<= 10000 kg\); "
        r"did you mean rotor_inertia = 5e-05 \(kg·cm\^2, reflecting 1\.01e\+03 kg\)\? "
        r"gear_ratio is 2 pi / lead \[rad/m\]"
    )
    with pytest.raises(DesignError, match=pattern):
        load_design(path)
    _cli_refuses(["modes", "--design", str(path)], capsys, pattern)
    fine = _edited(tmp_path, HEXAPOD, old, drive.format(5e-5))
    assert load_design(fine).legs[0].actuator.moving_parts().rotor == pytest.approx(1012.5)


def test_a_rotary_actuators_reflected_inertia_is_checked_too(tmp_path: Path) -> None:
    """3-RRR: 0.5 kg·m^2 through a 200:1 gear reflects 2e4 kg·m^2 onto the joint
    (refused); 5e-5 kg·m^2 (0.5 kg·cm^2) through it reflects 2 kg·m^2 (accepted)."""
    old = "threshold_displacement = 0.0\n"
    drive = "threshold_displacement = 0.0\nrotor_inertia = {}\ngear_ratio = 200.0\n"
    path = _edited(tmp_path, RRR, old, drive.format(0.5))
    with pytest.raises(DesignError, match=r"gear_ratio\^2 = 2e\+04 kg·m\^2 .*motor turns"):
        load_design(path)
    fine = _edited(tmp_path, RRR, old, drive.format(5e-5))
    assert load_design(fine).legs[0].actuator.moving_parts().rotor == pytest.approx(2.0)


def test_a_platform_lighter_than_a_milligram_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _edited(tmp_path, HEXAPOD, "mass = 1.766", "mass = 1e-30")
    pattern = r"key 'platform\.mass': mass = 1e-30: implausible mass, below 1e-06 kg"
    with pytest.raises(DesignError, match=pattern):
        load_design(path)
    _cli_refuses(["analyze", "--design", str(path)], capsys, pattern)
    tonnes = _edited(tmp_path, HEXAPOD, "mass = 1.766", "mass = 0.001766")
    assert load_design(tonnes).platform is not None  # 1.8 g: light, possible
    milli = _edited(tmp_path, HEXAPOD, "mass = 1.766", "mass = 1.766e-7")
    with pytest.raises(DesignError, match=r"did you mean 0\.0001766 \(t\)\?"):
        load_design(milli)


BUILTIN = ROOT / "src" / "ppm_stiffness" / "data" / "paper_3ppr.toml"


@pytest.mark.parametrize(
    ("old", "new", "refused"),
    [
        (
            "mass = 0.08505",
            "mass = 85.05",
            r"key 'leg\*': proximal\.mass = 85\.05: implausible density: a link of section "
            r"0\.00021 m\^2 and 0\.2236 m .*did you mean 0\.08505 \(g\)\? \(figures of leg1; "
            r"every leg alike\)$",
        ),
        (
            "mass_centre = 0.08",
            "mass_centre = 10.0",
            r"key 'leg\*': distal\.mass_centre = 10: .* longest length over its stroke is "
            r"0\.3436 m .*did you mean 0\.01 \(mm\)\? \(figures of leg1; every leg alike\)$",
        ),
    ],
)
def test_one_slip_in_every_leg_of_different_lengths_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], old: str, new: str, refused: str
) -> None:
    """The built-in's three legs differ in length, so the same slip in [parts] gave three
    messages with different figures, one a line (the 3-RPR's equal legs gave one): the
    same key, value and hint in every leg is one line under ``leg*``."""
    path = _edited(tmp_path, BUILTIN, old, new)
    with pytest.raises(DesignError, match=refused) as caught:
        load_design(path)
    assert len(str(caught.value).splitlines()) == 1
    _cli_refuses(["modes", "--design", str(path)], capsys, refused)


@pytest.mark.parametrize("command", ["sweep", "optimize"])
def test_a_vary_range_slipping_in_every_leg_is_one_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], command: str
) -> None:
    argv = [command, "--design", str(BUILTIN), "--vary", "leg*.distal.mass_centre=0.05:10"]
    if command == "sweep":
        argv[-1] += ":2"
    else:
        argv += ["--budget", "10", "--out", str(tmp_path / "o.toml")]
    _cli_refuses(
        [*argv, "--quiet"],
        capsys,
        r"HI = 10 m is refused by the design \(key 'leg\*': distal\.mass_centre = 10: .*"
        r"\(figures of leg1; every leg alike\)\)$",
    )
    assert not (tmp_path / "o.toml").exists()


@pytest.mark.parametrize(
    ("source", "old", "new", "refused"),
    [
        (
            BUILTIN,
            "carriage_mass = 0.2",
            "carriage_mass = 200.0",
            r"key 'leg\*': actuator\.carriage_mass = 200: implausible mass: 862 times the "
            r"platform's mass \(0\.232 kg\), above 100; masses are in kg: did you mean 0\.2 "
            r"\(g\)\?$",
        ),
        (
            ROOT / "examples" / "3prs.toml",
            "carriage_mass = 6.8",
            "carriage_mass = 6800.0",
            r"key 'leg\*': actuator\.carriage_mass = 6800: implausible mass: 472 times the "
            r"platform's mass \(14\.3965 kg\), above 100; .*did you mean 6\.8 \(g\)\?$",
        ),
    ],
)
def test_a_carriage_mass_in_grams_is_refused_against_the_platforms(
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    source: Path,
    old: str,
    new: str,
    refused: str,
) -> None:
    """A carriage mass in grams was accepted (200 kg on the built-in, 6800 kg on the
    3-PRS: below the 1e4 kg bound of any mass). 862 = 200 / 0.232, 472 = 6800 / 14.3965;
    the shipped carriages are 0.4 to 0.9 times their platform's mass."""
    path = _edited(tmp_path, source, old, new)
    with pytest.raises(DesignError, match=refused):
        load_design(path)
    _cli_refuses(["modes", "--design", str(path)], capsys, refused)
    assert load_design(source).legs[0].actuator.carriage_mass == float(old.split("= ")[1])


def test_a_threshold_displacement_beyond_the_stroke_is_refused(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """threshold_displacement = 6 (m) on the built-in, whose strokes are 50 mm, was
    accepted (the actuators then never left their locked branch); at the stroke it is
    accepted (no deflection exceeds it)."""
    path = _edited(
        tmp_path, BUILTIN, "threshold_displacement = 6e-06", "threshold_displacement = 6.0"
    )
    refused = (
        r"key 'leg\*': actuator\.threshold_displacement = 6: beyond the actuator's stroke "
        r"\(0\.05 m\), .*did you mean 0\.006 \(mm\)\?$"
    )
    with pytest.raises(DesignError, match=refused):
        load_design(path)
    _cli_refuses(["analyze", "--design", str(path)], capsys, refused)
    stroke = default_design().with_parameters({"actuator.threshold_displacement": 0.05})
    assert stroke.legs[0].actuator.threshold_displacement == 0.05


def test_a_platform_below_a_milligram_is_one_error_not_two(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """A 1e-30 kg platform on the 3-PRS: refused on its own; its carriages (6.8 kg,
    6.8e30 times it) are not measured against it (that second line read 'did you mean
    0.0068 (g)?' of a plausible carriage)."""
    path = _edited(tmp_path, ROOT / "examples" / "3prs.toml", "mass = 14.3965", "mass = 1e-30")
    _cli_refuses(
        ["modes", "--design", str(path)],
        capsys,
        r"key 'platform\.mass': mass = 1e-30: implausible mass, below 1e-06 kg",
    )
