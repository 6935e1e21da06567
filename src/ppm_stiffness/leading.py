"""Which sections an analysis leads with (``analyze``'s tables and JSON, the report's
embedded analyses): a planar design the paper's eq. (19) decoupling and its k_phi,
k_x, k_y; a spatial design the spatial principal stiffnesses (C = K^-1) and the
least-squares decoupling, eq. (19) on request (``--method paper``). The keys of an
analysis keep their meaning; :func:`leading_keys` adds ``planar``, ``leading`` and
``paper_definitions`` and :func:`lead` puts the leading blocks first."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from ppm_stiffness.core.decoupling import Method


def default_method(planar: bool) -> Method:
    """The decoupling shown first by default: eq. (19) for a planar design, the
    least-squares shift for a spatial one."""
    return "paper" if planar else "least-squares"


def leading_keys(planar: bool, asked: str | None) -> dict[str, Any]:
    """What the tables lead with (added to the JSON; the other keys keep their meaning).

    Parameters
    ----------
    planar : bool
        A planar design (or a ``--matrix``): the paper's eq. (19) decoupling and its
        k_phi, k_x, k_y first.
    asked : {"paper", "least-squares"} or None
        ``--method``; None: the default of the design's kind.

    Returns
    -------
    dict
        ``planar`` (bool), ``leading`` (the JSON keys of the sections shown first, in
        order) and ``paper_definitions`` (whether the paper's planar k_phi, k_x, k_y
        are printed).
    """
    paper = asked == "paper" or (asked is None and planar)
    if planar:
        leading = (
            ["decoupling", "principal"]
            if paper
            else ["decoupling_least_squares", "principal_least_squares"]
        )
    else:
        leading = ["principal_compliance", "decoupling_least_squares", "principal_least_squares"]
        if paper:
            leading = ["principal_compliance", "decoupling", "principal"]
    return {"planar": planar, "leading": leading, "paper_definitions": paper}


RESULT_SECTIONS = (
    "decoupling",
    "principal",
    "decoupling_least_squares",
    "principal_least_squares",
    "principal_compliance",
)


def lead(result: dict[str, Any]) -> dict[str, Any]:
    """``result`` with the sections of ``result["leading"]`` first among the
    decoupling and principal-stiffness blocks (same keys and values, JSON order)."""
    keys = list(result)
    first = min(keys.index(k) for k in RESULT_SECTIONS if k in result)
    blocks = [k for k in result.get("leading", []) if k in result]
    blocks += [k for k in RESULT_SECTIONS if k in result and k not in blocks]
    rest = [k for k in keys if k not in blocks]
    ordered = rest[:first] + blocks + rest[first:]
    return {k: result[k] for k in ordered}


__all__ = ["RESULT_SECTIONS", "default_method", "lead", "leading_keys"]
