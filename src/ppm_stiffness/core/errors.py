"""Errors raised for bad input. The CLI turns each into one line on stderr, exit 2."""

from __future__ import annotations


class PPMStiffnessError(Exception):
    """Base class of every error this library raises on purpose."""


class DesignError(PPMStiffnessError):
    """A design file or design parameter is malformed or non-physical."""


class UnreachablePoseError(PPMStiffnessError):
    """The pose lies outside the workspace (a stroke or a rod length is exceeded)."""


class SingularConfigurationError(PPMStiffnessError):
    """The configuration is singular: the stiffness matrix is (nearly) rank deficient."""


class InputDataError(PPMStiffnessError):
    """A matrix, wrench, CSV file or other numeric input is malformed."""


class DesignFormatWarning(FutureWarning):
    """A design file in an old format was read (it still loads; re-save it)."""


class EquilibriumError(PPMStiffnessError):
    """The loaded equilibrium could not be solved (no convergence)."""


class ImplausibleDesignWarning(UserWarning):
    """A design value that is possible but likely a mistake (it is used as given)."""
