"""``cached_property`` without the lock Python 3.10 and 3.11 take on every first access.

:class:`functools.cached_property` acquires a lock per first access on Python up to
3.11 (removed in 3.12 as a defect: it serialised every instance of a class).  A set's
facets, vertices and volume are each computed on first access, a few per set: the lock
cost about 4 % of building one polytope and its vertices on Python 3.11.  This subclass
is Python 3.12's behaviour, so documentation tools still see a ``cached_property``.
"""

from __future__ import annotations

import functools
from typing import Any, TypeVar, overload

__all__ = ["cached_property"]

_T = TypeVar("_T")


class cached_property(functools.cached_property[_T]):
    """:class:`functools.cached_property`, computed and stored without a lock."""

    @overload
    def __get__(self, instance: None, owner: type[Any] | None = None) -> cached_property[_T]: ...
    @overload
    def __get__(self, instance: object, owner: type[Any] | None = None) -> _T: ...
    def __get__(self, instance: object, owner: type[Any] | None = None) -> Any:
        if instance is None:
            return self
        value = instance.__dict__[self.attrname] = self.func(instance)  # type: ignore[index]
        return value
