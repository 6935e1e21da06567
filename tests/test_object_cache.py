"""Design-level data computed once per design object (issue 22, item 3): a leg's
reduced form is shared by every map call on the same design, recomputed for a changed
design, read-only, and dropped with its leg."""

from __future__ import annotations

import gc

import numpy as np
import pytest

import ppm_stiffness as pps
from ppm_stiffness.core.object_cache import per_object
from ppm_stiffness.maps.reduced_leg import leg_reduced_form, reduce_leg, reduced_design


class Thing:
    pass


def test_per_object_runs_once_per_live_object() -> None:
    calls: list[int] = []

    @per_object
    def derived(obj: object) -> list[int]:
        calls.append(id(obj))
        return [len(calls)]

    a, b = Thing(), Thing()
    assert derived(a) is derived(a)
    assert derived(b) == [2]
    assert calls == [id(a), id(b)]
    assert derived.cache_size() == 2  # type: ignore[attr-defined]
    del a
    gc.collect()
    assert derived.cache_size() == 1  # type: ignore[attr-defined]


def test_per_object_computes_each_time_without_weak_references() -> None:
    @per_object
    def double(x: int) -> int:
        return 2 * x

    assert double(21) == 42
    assert double.cache_size() == 0  # type: ignore[attr-defined]


def test_reduced_forms_are_computed_once_per_design() -> None:
    design = pps.default_design()
    first = reduced_design(design)
    assert first is not None
    again = reduced_design(design)
    assert again is not None
    assert all(a is b for a, b in zip(first, again, strict=True))
    assert reduce_leg(design, 1) is first[1]


def test_a_changed_design_gets_its_own_reduced_forms() -> None:
    design = pps.default_design()
    before = reduced_design(design)
    changed = design.with_parameters({"leg1.platform_radius": 0.9 * design.legs[0].platform_radius})
    after = reduced_design(changed)
    assert before is not None and after is not None
    assert after[0] is not before[0]
    fresh = changed.legs[0].reduced_form()  # the uncached computation
    assert after[0].radius == fresh.radius != before[0].radius
    np.testing.assert_array_equal(after[0].in_poly, fresh.in_poly)


def test_cached_reduced_forms_are_read_only() -> None:
    form = leg_reduced_form(pps.default_design().legs[0])
    with pytest.raises(ValueError, match="read-only"):
        form.in_poly[0] = 1.0
