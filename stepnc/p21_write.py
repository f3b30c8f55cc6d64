"""Part 21 writer: ``parse(''.join(write(f)))`` gives back ``f`` (ISO 10303-21 §7-§8)."""

from __future__ import annotations

from collections.abc import Iterator

from stepnc.p21_values import DERIVED, Binary, Enum, Instance, Part21File, Ref, Typed, encode_string


def format_value(v: object) -> str:
    """Part 21 text of one parameter value."""
    if v is None:
        return "$"
    if v is DERIVED:
        return "*"
    if isinstance(v, Ref):
        return f"#{int(v)}"
    if isinstance(v, bool):
        return ".T." if v else ".F."
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        r = repr(v)
        if "inf" in r or "nan" in r:
            raise ValueError(f"{v} has no Part 21 form")
        if "e" in r:
            mant, exp = r.split("e")
            if "." not in mant:
                mant += "."
            return f"{mant}E{exp}"
        return r
    if isinstance(v, Enum):
        return f".{v}."
    if isinstance(v, Binary):
        return f'"{v}"'
    if isinstance(v, str):
        return encode_string(v)
    if isinstance(v, Typed):
        return f"{v.name}({format_value(v.value)})"
    if isinstance(v, tuple):
        return "(" + ",".join(format_value(x) for x in v) + ")"
    raise TypeError(f"cannot write {v!r} as Part 21")


def format_instance(inst: Instance) -> str:
    if inst.name is None:
        body = "".join(f"{p.name}{format_value(p.params)}" for p in inst.params)
        return f"#{inst.id}=({body});"
    return f"#{inst.id}={inst.name}{format_value(inst.params)};"


def write(p21: Part21File) -> Iterator[str]:
    """Yield the lines of a Part 21 file; ``parse(''.join(write(f)))`` equals ``f``."""
    yield "ISO-10303-21;\n"
    yield "HEADER;\n"
    for name, params in p21.header:
        yield f"{name}{format_value(params)};\n"
    yield "ENDSEC;\n"
    yield "DATA;\n"
    for inst in p21.instances.values():
        yield format_instance(inst) + "\n"
    yield "ENDSEC;\n"
    yield "END-ISO-10303-21;\n"
