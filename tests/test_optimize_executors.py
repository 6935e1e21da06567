"""Serial, local processes and a real Dask cluster give identical sweeps and
optimisations (same seed: the same best parameters and objective, bit for bit)."""

from __future__ import annotations

from pathlib import Path

import pytest

import ppm_stiffness as pps
from ppm_stiffness.optimize.executors import open_executor, process_executor
from ppm_stiffness.optimize.objectives import OBJECTIVES
from ppm_stiffness.optimize.optimizer import optimize_design
from ppm_stiffness.optimize.region import make_region
from ppm_stiffness.optimize.sweep import sweep_designs
from ppm_stiffness.optimize.variables import parse_variable

ROOT = Path(__file__).parents[1]
REGION = make_region((-0.01, 0.01), (-0.01, 0.01), (-0.1, 0.1), (3, 2, 2))
WRENCH = [0.0, 0.0, 0.2, 5.0, -3.0, 0.0]


def _runs(executor: object) -> tuple[list[dict[str, float | None]], object]:
    design = pps.load_design(ROOT / "examples/3prr.toml")
    sweep_var = parse_variable("leg*.platform_radius=0.04:0.06:3", design, True)
    sweep = sweep_designs(
        design, [sweep_var], REGION, wrench=WRENCH, executor=executor, link_modes=0
    )
    variables = [
        parse_variable("leg*.platform_radius=0.04:0.07", design, False),
        parse_variable("leg1.actuator.locked_stiffness=1e7:4e7", design, False),
    ]
    result = optimize_design(
        design,
        variables,
        OBJECTIVES["max-displacement"],
        REGION,
        budget=10,
        seed=7,
        wrench=WRENCH,
        executor=executor,  # type: ignore[arg-type]
    )
    return [s.figures() for s in sweep.summaries], (
        result.best_parameters,
        result.best_objective,
        result.history,
        result.evaluations,
    )


@pytest.fixture(scope="module")
def serial() -> tuple[list[dict[str, float | None]], object]:
    with open_executor() as executor:
        return _runs(executor)


def test_local_processes_match_serial(serial: tuple[object, object]) -> None:
    with process_executor(2) as executor:
        assert _runs(executor) == serial  # exactly equal, not approximately


def test_dask_local_cluster_matches_serial(serial: tuple[object, object]) -> None:
    try:
        from distributed import LocalCluster
    except ImportError:
        pytest.skip("distributed is not installed (pip install -e '.[dask]')")
    # a real scheduler and 2 workers talking over TCP on the loopback interface; the
    # workers are threads of this process (processes=False) to keep the test short:
    # separate processes are the test above
    with LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=False,
        protocol="tcp",
        host="127.0.0.1",
        dashboard_address=None,
    ) as cluster:
        with open_executor(scheduler=cluster.scheduler_address) as executor:
            assert _runs(executor) == serial
