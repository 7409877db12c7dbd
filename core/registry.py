"""The one registry helper: named objects users pick by the name they type.

Every registry of the harness (MIMO schemes, receive chains, chips, boards, CFAR modes, tracker
parts, scenario cases, ...) is a `Registry`: a read-only mapping from name to object with
`register` (refuses a taken name unless ``replace=True``, and objects of the wrong type;
``registry[name] = obj`` registers too, replacing),
`lookup` (a `ValueError` that names the field, the value and every known name) and `freeze`
(no more registrations: for closed vocabularies such as TI's ADC output formats). It lives in
`core`, below every package, so a lab registers its own board exactly as it registers a
scheme.

Every entry remembers the module that registered it (`Registry.origin`: the first caller
outside this module and outside ``register*`` helpers such as ``radarsim.register_scheme``), so
`radar-harness plugins` can say which entries are built in and which a plugin added. Every
registry is listed by `all_registries`; `registry_state` / `restore_registry_state` undo the
registrations of a plugin that fails half-way through its import.

Examples
--------
>>> from core.registry import Registry
>>> WINDOWS = Registry("window", field="window")
>>> WINDOWS.register("hann", name="hann")
'hann'
>>> WINDOWS.lookup("hann")
'hann'
>>> WINDOWS.lookup("kaiser")
Traceback (most recent call last):
...
core.errors.BadInput: window='kaiser' is not one of ['hann']
"""
from __future__ import annotations

import sys
import weakref
from collections.abc import Iterable, Iterator, Mapping
from typing import Any, Generic, TypeVar

from .errors import BadInput

__all__ = ["Registry", "unknown_name_message", "all_registries", "registry_state",
           "restore_registry_state"]

T = TypeVar("T")

#: Every registry created in this process (weak references: a test's throwaway registry may
#: go away; a Mapping is unhashable, so a list, not a WeakSet).
_ALL: "list[weakref.ref[Registry]]" = []
#: Caller functions that only forward a registration (their caller is the origin).
_FORWARDERS = ("setdefault", "__setitem__")


def _registering_module() -> str:
    """Module of the code that asked for a registration: the first frame outside this module
    whose function is not a ``register*`` forwarder (``radarsim.register_scheme``,
    ``Registry.register_all``, a package's ``_register`` helper)."""
    frame = sys._getframe(1)
    while frame is not None:
        module = frame.f_globals.get("__name__", "?")
        name = frame.f_code.co_name
        if module != __name__ and not name.lstrip("_").startswith("register") \
                and name not in _FORWARDERS:
            return module
        frame = frame.f_back
    return "?"


def all_registries() -> list["Registry"]:
    """Every live registry, sorted by what an entry is (`Registry.what`)."""
    live = [r for r in (ref() for ref in _ALL) if r is not None]
    _ALL[:] = [weakref.ref(r) for r in live]
    return sorted(live, key=lambda r: r.what.lower())


def registry_state() -> list:
    """A copy of every registry's entries and origins (for `restore_registry_state`)."""
    return [(r, dict(r._items), dict(r._origins)) for r in all_registries()]


def restore_registry_state(state: list) -> None:
    """Put every registry of `state` back as it was (a failed plugin leaves nothing behind);
    registries created since keep their entries."""
    for reg, items, origins in state:
        reg._items.clear()
        reg._items.update(items)
        reg._origins.clear()
        reg._origins.update(origins)


def unknown_name_message(field: str, value: Any, known: Iterable) -> str:
    """``{field}={value!r} is not one of [...]``: the message of every failed lookup."""
    return f"{field}={value!r} is not one of {sorted(map(str, known))}"


class Registry(Mapping[str, T], Generic[T]):
    """A read-only name -> object mapping with checked registration and lookup.

    Parameters
    ----------
    what : str
        What an entry is, for messages ("scheme", "chip", "CFAR mode").
    field : str, optional
        The config field or key users type the name into ("mimo", "chip", "mode"); lookup
        errors read ``{field}={name!r} is not one of [...]``. Default `what`.
    kind : type, optional
        Entries must be instances of it.
    identifier : bool
        Names must be Python identifiers (names that become columns or attributes).
    missing : str, optional
        Format of the lookup error instead of the default, with ``{field}``, ``{name}`` (the
        repr of the value) and ``{known}`` (the sorted names).
    """

    def __init__(self, what: str, *, field: str | None = None, kind: type | None = None,
                 identifier: bool = False, missing: str | None = None) -> None:
        self.what = what
        self.field = field or what
        self.kind = kind
        self.identifier = identifier
        self._missing = missing
        self._items: dict[str, T] = {}
        self._origins: dict[str, str] = {}
        self._frozen = False
        _ALL.append(weakref.ref(self))

    # ------------------------------------------------------------------ Mapping
    def __getitem__(self, name: str) -> T:
        return self._items[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._items)

    def __len__(self) -> int:
        return len(self._items)

    def __setitem__(self, name: str, obj: T) -> None:
        """``registry[name] = obj``: `register` under `name`, replacing an entry of that name
        (the dict idiom, with the registry's checks)."""
        self.register(obj, name=name, replace=True)

    def setdefault(self, name: str, obj: T) -> T:
        """The entry `name`, registering `obj` under it first if there is none (the dict
        idiom, with the registry's checks)."""
        if name not in self._items:
            self.register(obj, name=name)
        return self._items[name]

    def __delitem__(self, name: str) -> None:
        """``del registry[name]``: `unregister`."""
        self.unregister(name)

    def __repr__(self) -> str:
        return f"Registry({self.what!r}: {', '.join(self._items)})"

    # ------------------------------------------------------------------ registration
    @property
    def frozen(self) -> bool:
        """True once `freeze` was called: `register` and `unregister` then refuse."""
        return self._frozen

    def register(self, obj: T, *, name: str | None = None, replace: bool = False) -> T:
        """Add `obj` under `name` (default ``obj.name``) and return it.

        Raises
        ------
        ValueError
            Frozen registry, wrong type, empty (or non-identifier) name, or a taken name
            without ``replace``.
        """
        if self._frozen:
            raise BadInput(f"the {self.what} registry is frozen: {list(self._items)}")
        if not isinstance(replace, bool):
            raise BadInput(f"replace={replace!r} must be true or false")
        if self.kind is not None and not isinstance(obj, self.kind):
            raise BadInput(f"{self.what} must be a {self.kind.__name__}, got "
                           f"{type(obj).__name__}")
        name = getattr(obj, "name", None) if name is None else name
        if not isinstance(name, str) or not name or \
                (self.identifier and not name.isidentifier()):
            need = "a non-empty identifier" if self.identifier else "a non-empty string"
            raise BadInput(f"{self.what} name={name!r} must be {need}")
        if name in self._items and not replace:
            raise BadInput(f"{self.what} name={name!r} is already registered")
        self._items[name] = obj
        self._origins[name] = _registering_module()
        return obj

    def register_all(self, objs: Iterable[T]) -> "Registry[T]":
        """`register` every object (by its ``name``); returns the registry."""
        for obj in objs:
            self.register(obj)
        return self

    def unregister(self, name: str) -> T:
        """Remove and return the entry `name` (a test's or a lab's own entry).

        Raises
        ------
        ValueError
            Frozen registry or unknown name.
        """
        if self._frozen:
            raise BadInput(f"the {self.what} registry is frozen: {list(self._items)}")
        obj = self.lookup(name)
        del self._items[name]
        self._origins.pop(name, None)
        return obj

    def origin(self, name: str) -> str:
        """Module that registered the entry `name` (``"?"`` when unknown).

        Raises
        ------
        ValueError
            Unknown name (as `lookup`).
        """
        self.lookup(name)
        return self._origins.get(name, "?")

    def freeze(self) -> "Registry[T]":
        """Refuse further registrations (a closed vocabulary); returns the registry."""
        self._frozen = True
        return self

    # ------------------------------------------------------------------ lookup
    def lookup(self, name: Any) -> T:
        """The entry `name`.

        Raises
        ------
        ValueError
            ``{field}={name!r} is not one of [...]`` (every known name), or the `missing`
            format given at construction.
        """
        try:
            return self._items[name]
        except (KeyError, TypeError):  # TypeError: an unhashable value is simply not found
            raise BadInput(self.missing_message(name)) from None

    def missing_message(self, name: Any) -> str:
        """The message `lookup` raises for an unknown `name`."""
        if self._missing is not None:
            return self._missing.format(field=self.field, name=repr(name),
                                        known=sorted(map(str, self._items)))
        return unknown_name_message(self.field, name, self._items)
