"""``kernel.record.record`` makes what ``@dataclass(frozen=True, slots=True)`` makes.

The reference is ``dataclasses`` itself: each class below is declared twice, once with each
decorator, and every behaviour the toolchain relies on (construction, defaults, keyword-only
fields, equality and hash without ``compare=False`` fields, ``repr``, pattern matching,
``fields``/``replace``/``asdict``, pickling and copying, immutability, a ``@dataclass``
subclass) is compared between the two; then the IR's own classes are checked the same way.
"""

from __future__ import annotations

import copy
import dataclasses
import inspect
import pickle
from dataclasses import dataclass, field
from typing import Any, ClassVar

import pytest

from kernel.diagnostics import Location
from kernel.ir import canon
from kernel.record import record


@dataclass(frozen=True, slots=True)
class DBase:
    NAME: ClassVar[str] = ""
    source: object = field(default=None, compare=False, kw_only=True, repr=False)


@record
class RBase:
    NAME: ClassVar[str] = ""
    source: object = field(default=None, compare=False, kw_only=True, repr=False)


@dataclass(frozen=True, slots=True)
class DMove(DBase):
    NAME: ClassVar[str] = "MOVE"
    x: float
    y: float
    tag: str = "t"


@record
class RMove(RBase):
    NAME: ClassVar[str] = "MOVE"
    x: float
    y: float
    tag: str = "t"


@dataclass(frozen=True, slots=True)
class DOne(DBase):
    n: int


@record
class ROne(RBase):
    n: int


@dataclass(frozen=True, slots=True)
class DEmpty(DBase):
    pass


@record
class REmpty(RBase):
    pass


@dataclass(frozen=True, slots=True)
class DPlain:
    a: int = 1
    b: tuple[int, ...] = ()


@record
class RPlain:
    a: int = 1
    b: tuple[int, ...] = ()


PAIRS: list[tuple[type, type, tuple[Any, ...], dict[str, Any]]] = [
    (DMove, RMove, (1.0, 2.0), {}),
    (DMove, RMove, (1.0, 2.0, "u"), {"source": "here"}),
    (DOne, ROne, (3,), {"source": 7}),
    (DEmpty, REmpty, (), {}),
    (DPlain, RPlain, (), {}),
    (DPlain, RPlain, (2, (1, 2)), {}),
]


def _field_view(cls: type) -> list[tuple[object, ...]]:
    return [
        (f.name, f.type, f.default, f.kw_only, f.compare, f.repr, f.hash, f.init)
        for f in dataclasses.fields(cls)
    ]


@pytest.mark.parametrize("dcls, rcls, args, kwargs", PAIRS)
def test_record_behaves_as_a_frozen_slots_dataclass(
    dcls: type, rcls: type, args: tuple[Any, ...], kwargs: dict[str, Any]
) -> None:
    d, r = dcls(*args, **kwargs), rcls(*args, **kwargs)
    assert dataclasses.is_dataclass(r)
    assert _field_view(rcls) == _field_view(dcls)
    assert rcls.__match_args__ == dcls.__match_args__
    assert rcls.__dict__["__slots__"] == dcls.__dict__["__slots__"]
    assert str(inspect.signature(rcls)) == str(inspect.signature(dcls))
    assert repr(r).replace("R", "D", 1) == repr(d)
    assert dataclasses.asdict(r) == dataclasses.asdict(d)
    assert dataclasses.astuple(r) == dataclasses.astuple(d)
    # equality and hash: by the compared fields only, and only within one class
    again = rcls(*args)
    assert r == again and hash(r) == hash(again)
    assert hash(r) == hash(d)  # the same tuple of values is hashed
    assert r != d and r != object()
    assert not hasattr(r, "__dict__")
    for clone in (pickle.loads(pickle.dumps(r)), copy.copy(r), copy.deepcopy(r)):
        assert clone == r and repr(clone) == repr(r)
        assert getattr(clone, "source", None) == getattr(r, "source", None)
    for name in [f.name for f in dataclasses.fields(rcls)] + ["other"]:
        with pytest.raises(AttributeError):
            setattr(r, name, 1)
    if dataclasses.fields(rcls):
        name = dataclasses.fields(rcls)[0].name
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(r, name, 1)
        with pytest.raises(dataclasses.FrozenInstanceError):
            delattr(r, name)


def test_record_arguments_are_checked_as_by_a_dataclass() -> None:
    for cls in (DMove, RMove):
        with pytest.raises(TypeError):
            cls(1.0)
        with pytest.raises(TypeError):
            cls(1.0, 2.0, "t", 4)
        with pytest.raises(TypeError):
            cls(1.0, 2.0, source=1, other=2)
        assert cls(y=2.0, x=1.0) == cls(1.0, 2.0)


def test_record_pattern_matching_and_replace() -> None:
    r = RMove(1.0, 2.0, source="s")
    match r:
        case RMove(x, y, tag=t):
            assert (x, y, t) == (1.0, 2.0, "t")
        case _:
            pytest.fail("no match")
    moved = dataclasses.replace(r, y=5.0)
    assert (moved.x, moved.y, moved.source) == (1.0, 5.0, "s")


def test_a_dataclass_may_extend_a_record() -> None:
    @dataclass(frozen=True, slots=True)
    class Extra(RMove):
        z: float = 0.0

    e = Extra(1.0, 2.0, "t", 3.0, source="s")
    assert [f.name for f in dataclasses.fields(e)] == ["source", "x", "y", "tag", "z"]
    assert e == Extra(1.0, 2.0, "t", 3.0) and e != Extra(1.0, 2.0, "t", 4.0)
    assert e.source == "s"
    with pytest.raises(dataclasses.FrozenInstanceError):
        e.z = 1.0  # type: ignore[misc]


def test_record_refuses_what_it_does_not_support() -> None:
    with pytest.raises(TypeError):

        @record
        class Factory:
            items: list[int] = field(default_factory=list)

    with pytest.raises(TypeError):

        @record
        class Order:
            a: int = 1
            b: int


_SAMPLE: dict[str, object] = {"int": 2, "str": "s", "bool": True}


@pytest.mark.parametrize("cls", canon.ALL_COMMANDS + (Location,), ids=lambda c: c.__name__)
def test_ir_classes_keep_their_dataclass_shape(cls: type) -> None:
    """Every IR class: fields in NISTIR order after ``source``, equality without ``source``,
    pickling with it (the cluster sends commands pickled)."""
    names = [f.name for f in dataclasses.fields(cls)]
    values: list[object] = []
    for f in dataclasses.fields(cls):
        if f.kw_only or f.default is not dataclasses.MISSING:
            continue
        kind = str(f.type)
        values.append((1.5,) * 9 if kind.startswith("tuple") else _SAMPLE.get(kind, 1.5))
    if cls is Location:
        assert names == ["file", "line", "column", "entity", "workingstep"]
        obj = Location("f", 3, 4)
        assert pickle.loads(pickle.dumps(obj)) == obj and hash(obj) == hash(Location("f", 3, 4))
        return
    assert names[0] == "source"
    here = Location("p.ngc", 1, 1)
    a, b = cls(*values, source=here), cls(*values)
    assert a == b and hash(a) == hash(b) and a.source == here
    back = pickle.loads(pickle.dumps(a))
    assert back == a and back.source == here and back.to_text() == a.to_text()
