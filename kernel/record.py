"""``@record``: ``@dataclass(frozen=True, slots=True)`` made cheaply, for the IR's many classes.

The IR (``kernel.ir.canon``) has about seventy small immutable classes and the interpreter
creates one per canonical command and a :class:`~kernel.diagnostics.Location` per line.
``dataclasses`` compiles six or seven functions per class when the module is imported (about
0.7 ms a class: half of ``cnc canon``'s start-up was spent there), and its frozen
``__init__`` sets each field through ``object.__setattr__``. ``record`` makes the same
class: the same slots, ``__init__`` signature, equality, hash, ``repr``, pattern-matching
positions, pickling and ``FrozenInstanceError`` on assignment, and ``dataclasses.fields``,
``replace``, ``asdict`` and a ``@dataclass`` subclass work on it as on a dataclass. It
compiles one ``__init__`` per number of fields (its parameters renamed for each class) that
stores each value through its slot's descriptor, and shares one ``__eq__``,
``__hash__`` and ``__repr__`` between all classes.

Supported: annotated fields with or without a plain default, ``ClassVar`` annotations, and
``dataclasses.field(default=..., compare=..., repr=..., hash=..., kw_only=...)``; a single
base class, itself a record or a frozen dataclass (or ``object``). Anything else (a
``default_factory``, ``InitVar``, a mutable default) raises ``TypeError`` at import time.
"""

from __future__ import annotations

import builtins
import dataclasses
import types
from collections.abc import Callable
from operator import attrgetter
from typing import Any, TypeVar, cast, dataclass_transform

T = TypeVar("T", bound=type)

_MISSING = dataclasses.MISSING
#: the ``dataclasses`` marker of a real field (what ``fields()`` keeps): public
#: ``dataclasses`` has no constructor for a finished Field; tests/test_record.py checks that
#: ``fields``, ``replace``, ``asdict`` and ``@dataclass`` subclasses work with it
_FIELD_MARKER = vars(dataclasses)["_FIELD"]


class _Params:
    """``__dataclass_params__`` of a record: frozen, with equality, no ordering."""

    __slots__ = ()
    init = True
    repr = True
    eq = True
    order = False
    unsafe_hash = False
    frozen = True
    match_args = True
    kw_only = False
    slots = True
    weakref_slot = False


_PARAMS = _Params()
#: compiled ``__init__`` code by (number of positional fields, number of keyword-only ones)
_INIT_CODE: dict[tuple[int, int], Any] = {}


def _is_classvar(annotation: object) -> bool:
    text = annotation if isinstance(annotation, str) else repr(annotation)
    return text.startswith(("ClassVar", "typing.ClassVar"))


def _make_field(name: str, annotation: object, value: object) -> Any:
    f: Any
    if isinstance(value, dataclasses.Field):
        f = value
        if f.default_factory is not _MISSING or not f.init:
            raise TypeError(f"record field {name}: default_factory and init=False unsupported")
    else:
        if isinstance(value, list | dict | set):
            raise TypeError(f"record field {name}: mutable default {value!r}")
        f = dataclasses.field(default=value)
        f.kw_only = False
    if f.kw_only is _MISSING:
        f.kw_only = False
    f.name = name
    f.type = annotation
    f._field_type = _FIELD_MARKER
    return f


def _init_function(
    positional: list[Any],
    keyword: list[Any],
    setters: list[Callable[[object, object], None]],
    qualname: str,
) -> Any:
    """``__init__(self, <positional>, *, <keyword>)`` storing each argument by its slot's
    ``__set__`` (``_s0``, ``_s1``, ... in the function's globals)."""
    pos_names = tuple(f.name for f in positional)
    kw_names = tuple(f.name for f in keyword)
    shape = (len(pos_names), len(kw_names))
    template = _INIT_CODE.get(shape)
    if template is None:
        args = [f"a{i}" for i in range(shape[0])]
        kwargs = [f"k{i}" for i in range(shape[1])]
        params = ", ".join(["self", *args, *(["*", *kwargs] if kwargs else [])])
        body = "".join(f"    _s{i}(self, {n})\n" for i, n in enumerate(args + kwargs))
        scope: dict[str, Any] = {}
        exec(compile(f"def __init__({params}):\n{body or '    pass'}\n", "<record>", "exec"), scope)
        template = scope["__init__"].__code__
        _INIT_CODE[shape] = template
    # the same code with the fields' names as its parameters' (the body reads them by index)
    code = template.replace(
        co_varnames=("self", *pos_names, *kw_names), co_qualname=f"{qualname}.__init__"
    )
    env: dict[str, Any] = {f"_s{i}": s for i, s in enumerate(setters)}
    env["__builtins__"] = builtins
    defaults = tuple(f.default for f in positional if f.default is not _MISSING)
    fn = types.FunctionType(code, env, "__init__", defaults or None)
    fn.__kwdefaults__ = {f.name: f.default for f in keyword if f.default is not _MISSING} or None
    fn.__qualname__ = f"{qualname}.__init__"
    fn.__annotations__ = {f.name: f.type for f in positional + keyword} | {"return": None}
    return fn


def _key_getter(names: tuple[str, ...]) -> Callable[[object], tuple[object, ...]]:
    """The tuple of ``names``' values, as the dataclass ``__eq__`` and ``__hash__`` build it."""
    if not names:
        return lambda self: ()
    if len(names) == 1:
        one = attrgetter(names[0])
        return lambda self: (one(self),)
    many: Callable[[object], tuple[object, ...]] = attrgetter(*names)
    return many


def _eq(self: Any, other: Any) -> Any:
    if other.__class__ is self.__class__:
        key = self._record_key
        return bool(key(self) == key(other))
    return NotImplemented


def _hash(self: Any) -> int:
    return hash(self._record_key(self))


def _repr(self: Any) -> str:
    parts = ", ".join(f"{n}={getattr(self, n)!r}" for n in self._record_repr)
    return f"{self.__class__.__qualname__}({parts})"


def _setattr(self: object, name: str, value: object) -> None:
    raise dataclasses.FrozenInstanceError(f"cannot assign to field {name!r}")


def _delattr(self: object, name: str) -> None:
    raise dataclasses.FrozenInstanceError(f"cannot delete field {name!r}")


def _getstate(self: Any) -> list[object]:
    return [getattr(self, n) for n in self._record_names]


def _setstate(self: Any, state: list[object]) -> None:
    for setter, value in zip(self._record_setters, state, strict=True):
        setter(self, value)


@dataclass_transform(frozen_default=True, field_specifiers=(dataclasses.field, dataclasses.Field))
def record(cls: T) -> T:
    """The class ``@dataclass(frozen=True, slots=True)`` would make of ``cls`` (see the
    module's docstring for what it supports)."""
    (base,) = cls.__bases__
    inherited: dict[str, Any] = dict(getattr(base, "__dataclass_fields__", {}))
    if inherited and not getattr(base, "__dataclass_params__", _PARAMS).frozen:
        raise TypeError(f"{cls.__qualname__}: a record's base must be frozen")
    ns = cls.__dict__
    own: dict[str, Any] = {}
    for name, annotation in ns.get("__annotations__", {}).items():
        if _is_classvar(annotation):
            continue
        own[name] = _make_field(name, annotation, ns.get(name, _MISSING))
    fields = {**inherited, **{k: v for k, v in own.items() if k not in inherited}}
    body = {k: v for k, v in ns.items() if k not in own and k not in ("__dict__", "__weakref__")}
    body["__slots__"] = tuple(n for n in own if n not in inherited)
    new: Any = type(cls)(cls.__name__, cls.__bases__, body)
    new.__qualname__ = cls.__qualname__
    every = list(fields.values())
    positional = [f for f in every if not f.kw_only]
    keyword = [f for f in every if f.kw_only]
    seen_default = False
    for f in positional:
        if f.default is not _MISSING:
            seen_default = True
        elif seen_default:
            raise TypeError(f"non-default argument {f.name!r} follows default argument")
    order = positional + keyword
    setters = [_slot_setter(new, f.name) for f in order]
    new.__init__ = _init_function(positional, keyword, setters, cls.__qualname__)
    attributes = {
        "__dataclass_fields__": fields,
        "__dataclass_params__": _PARAMS,
        "__match_args__": tuple(f.name for f in positional),
    }
    for name, value in attributes.items():
        setattr(new, name, value)
    compare = tuple(f.name for f in every if f.compare)
    hashed = tuple(f.name for f in every if (f.compare if f.hash is None else f.hash))
    new._record_key = staticmethod(_key_getter(compare))
    if hashed != compare:
        raise TypeError(f"{cls.__qualname__}: hash=... different from compare=... unsupported")
    new._record_repr = tuple(f.name for f in every if f.repr)
    new._record_names = tuple(f.name for f in order)
    new._record_setters = tuple(setters)
    for name, fn in (
        ("__eq__", _eq),
        ("__hash__", _hash),
        ("__repr__", _repr),
        ("__setattr__", _setattr),
        ("__delattr__", _delattr),
        ("__getstate__", _getstate),
        ("__setstate__", _setstate),
    ):
        if name not in body or (name == "__hash__" and body[name] is None):
            setattr(new, name, fn)
    return cast(T, new)


def _slot_setter(cls: type, name: str) -> Callable[[object, object], None]:
    """The ``__set__`` of the slot ``name`` (the class's own or a base's)."""
    for klass in cls.__mro__:
        slot = klass.__dict__.get(name)
        if slot is not None and hasattr(slot, "__set__"):
            setter: Callable[[object, object], None] = slot.__set__
            return setter
    raise TypeError(f"{cls.__qualname__}: no slot for field {name!r}")
