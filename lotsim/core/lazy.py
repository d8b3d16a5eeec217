"""Attributes worked out when first read: :class:`LoadedBy`, lotsim's one way of being lazy.

A lot loaded from the on-disk cache keeps its graph and its maneuver answers packed until
something reads them (a warm ``lotsim validate`` never does, and never imports networkx);
a lot's maneuvers put their pieces in the world only when they are driven. Each such
attribute is declared on its class as ``LoadedBy("load_x")``: reading it while it is not
set calls the owner's ``load_x()``, which sets it (and whatever else it loads with it) on
the instance; from then on the instance's own attribute is read, as
:func:`functools.cached_property` reads its value. A caller who wants the work done now
calls ``load_x()`` itself.

Examples
--------
>>> class Box:
...     contents = LoadedBy("load_contents")
...     def load_contents(self):
...         print("unpacking")
...         self.contents = [1, 2]
>>> box = Box()
>>> box.contents
unpacking
[1, 2]
>>> box.contents
[1, 2]
"""

from __future__ import annotations

from typing import Any


class LoadedBy:
    """An attribute its owner's method ``load`` sets when it is first read (see the
    module's docstring). Read from the class, it is missing (so that a dataclass field
    declared so has no default); a ``load`` that does not set it leaves it missing."""

    __slots__ = ("load", "name")

    def __init__(self, load: str) -> None:
        self.load = load
        self.name = ""

    def __set_name__(self, owner: type, name: str) -> None:
        self.name = name

    def __get__(self, obj: object, owner: type | None = None) -> Any:
        if obj is None:
            raise AttributeError(self.name)
        getattr(obj, self.load)()
        try:
            return obj.__dict__[self.name]
        except KeyError:
            raise AttributeError(f"{type(obj).__name__!r} object has no attribute "
                                 f"{self.name!r}") from None
