"""The report's "Natural frequencies" section (visuals/report_dynamics.py): the modal
analysis embedded and traced to the printed digits, the mode-shape picture and the f1
map; nothing for a design without a mass model."""

from __future__ import annotations

import base64
import io
import json
import re

import matplotlib

matplotlib.use("Agg")

import matplotlib.image as mpimg  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from helpers import colour_count, design_named  # noqa: E402
from ppm_stiffness.analysis import ENVELOPE_KEYS, dump_json  # noqa: E402
from ppm_stiffness.design import design_from_dict, design_to_dict  # noqa: E402
from ppm_stiffness.dynamics.analysis import modal_analysis  # noqa: E402
from ppm_stiffness.maps.workspace import stiffness_map  # noqa: E402
from ppm_stiffness.poses import home_pose  # noqa: E402
from ppm_stiffness.visuals.report import embedded_json  # noqa: E402
from ppm_stiffness.visuals.report_dynamics import dynamics_sections  # noqa: E402
from report_cells import check_cells, parse  # noqa: E402

GRID = 8


@pytest.fixture(scope="module", params=["paper", "hexapod_6ups"])
def section(request: pytest.FixtureRequest) -> tuple[str, str]:
    design = design_named(request.param)
    found = dynamics_sections(design, home_pose(design), GRID)
    assert len(found) == 1
    sid, title, html = found[0]
    assert sid == "dynamics"
    return request.param, f"<h2>{title}</h2>" + html


def test_the_embedded_analysis_is_modal_analysis_and_every_number_traces_to_it(
    section: tuple[str, str],
) -> None:
    """The block is ``modal_analysis`` at the pose (at P, locked); the masses, the six
    frequencies and their shares are printed from it, to their digits; the title's f1
    is the first frequency."""
    name, html = section
    design = design_named(name)
    expected = json.loads(dump_json(modal_analysis(design, home_pose(design), None, np.zeros(3))))
    embedded = embedded_json(html, "analysis-modes")
    assert {k: v for k, v in embedded.items() if k not in ENVELOPE_KEYS} == expected
    cells = parse(html).cells
    paths = {c[0] for c in cells}
    assert all(f"modes/frequencies/{j}" in paths for j in range(6))
    assert all(f"modes/modes/{j}/share" in paths for j in range(6))
    assert "modes/masses/total" in paths
    check_cells(cells, {"modes": embedded})
    title = re.search(r"f<sub>1</sub> = ([0-9.]+) Hz\)</h2>", html)
    assert title is not None
    f1 = expected["frequencies"][0]
    assert abs(float(title.group(1)) - f1) <= 0.5 * 10 ** (np.floor(np.log10(f1)) - 3) * (1 + 1e-9)
    assert f"({expected['modes'][0]['direction']})" in html


def test_the_mode_shapes_and_the_f1_map_are_drawn(section: tuple[str, str]) -> None:
    """Two drawings (the modes, the f1 map), and the caption's f1 range is the map's."""
    name, html = section
    page = parse(html)
    assert {"fig-modes", "fig-f1-map"} <= page.ids
    assert len(page.images) == 2
    for src in page.images:
        raw = base64.b64decode(src.split(",", 1)[1], validate=True)
        img = mpimg.imread(io.BytesIO(raw), format="png")
        assert img.shape[0] > 250 and colour_count(img) > 50
    design = design_named(name)
    smap = stiffness_map(design, grid=GRID, quantities=["f1"])
    s = smap.summary()["f1"]
    assert f"{s['min']:.4g} Hz to {s['max']:.4g} Hz" in html


def test_no_section_without_a_mass_model() -> None:
    data = design_to_dict(design_named("paper"))
    del data["platform"]
    for table in data["parts"].values():
        for key in ("mass", "mass_centre", "mass_centre_from", "inertia_transverse"):
            table.pop(key, None)
        table.pop("carriage_mass", None)
    design = design_from_dict(data)
    assert not design.has_mass_model
    assert dynamics_sections(design, home_pose(design), GRID) == []
