"""What the typed results of the public API share: their plain-data form, and the
mapping access of the dicts they replace, deprecated.

:func:`ppm_stiffness.analyze` and :func:`ppm_stiffness.modal_analysis` returned dicts
until 0.2; they return dataclasses since 0.3, whose ``to_dict()`` is the dict of
before, key for key (the ``--json`` document of ``analyze``/``modes`` is built from it).
``result["key"]``, ``"key" in result``, iterating over the keys, ``result.get``,
``keys``, ``items`` and ``values`` still work, on that dict, with a
:class:`DeprecationWarning`, until 0.4 (``docs/compatibility.md``).
"""

from __future__ import annotations

import warnings
from collections.abc import ItemsView, Iterator, KeysView, ValuesView
from typing import Any

#: The release that removes the deprecated names and mapping access of 0.2.
REMOVED_IN = "0.4"


class DeprecatedMapping:
    """Mixin: read-only mapping access on ``self.to_dict()``, each with a
    DeprecationWarning that names the replacement."""

    def to_dict(self) -> dict[str, Any]:  # pragma: no cover - defined by each result
        raise NotImplementedError

    def _warn_mapping(self, what: str) -> dict[str, Any]:
        name = type(self).__name__
        warnings.warn(
            f"{what} (mapping access on {name}) is deprecated since 0.3: use its "
            f"attributes, or .to_dict() for the dict of 0.2; removed in {REMOVED_IN}",
            DeprecationWarning,
            stacklevel=3,
        )
        return self.to_dict()

    def __getitem__(self, key: str) -> Any:
        return self._warn_mapping(f"result[{key!r}]")[key]

    def __contains__(self, key: object) -> bool:
        return key in self._warn_mapping(f"{key!r} in result")

    def __iter__(self) -> Iterator[str]:
        return iter(self._warn_mapping("iterating over result"))

    def get(self, key: str, default: Any = None) -> Any:
        """``to_dict().get(key, default)`` (deprecated)."""
        return self._warn_mapping(f"result.get({key!r})").get(key, default)

    def keys(self) -> KeysView[str]:
        """``to_dict().keys()`` (deprecated)."""
        return self._warn_mapping("result.keys()").keys()

    def items(self) -> ItemsView[str, Any]:
        """``to_dict().items()`` (deprecated)."""
        return self._warn_mapping("result.items()").items()

    def values(self) -> ValuesView[Any]:
        """``to_dict().values()`` (deprecated)."""
        return self._warn_mapping("result.values()").values()
