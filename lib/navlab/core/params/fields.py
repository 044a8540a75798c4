"""Helpers shared by the params.yaml section schemas: the ``section`` decorator and ``between`` ranges.

pydantic checks a profile against them when it is loaded (``navlab.core.params.load_params``). The
sections stay plain frozen dataclasses: attribute access, ``dataclasses.replace``/``asdict``, hashing and
pickling work as before, and a variant built in code with ``replace`` is not re-checked (the stage that
reads it names a bad value itself).
"""

from __future__ import annotations

import dataclasses
from typing import Annotated, Any, get_args, get_origin

from pydantic import ConfigDict, GetCoreSchemaHandler
from pydantic_core import CoreSchema, PydanticCustomError, core_schema

PROFILES = ("smoke", "default", "gpu", "paper")  # gpu: PACER at a CUDA-machine size (pacer only; else default)

# strict: no "3" for a number, no true for an integer, no 1 for true; an integer where a number is
# declared is taken and becomes a float. extra="forbid": a misspelt key is an error, not ignored.
CONFIG = ConfigDict(strict=True, extra="forbid", allow_inf_nan=False)


def section(cls: type) -> type:
    """A frozen dataclass for one params.yaml mapping, checked by pydantic at load time, with its
    ``min_<x>``/``max_<x>`` pairs in order (an empty range fails much later). Give no field a default:
    pydantic would let params.yaml leave that key out, and every profile must state every value."""
    cls = dataclasses.dataclass(frozen=True)(cls)
    defaults = [f.name for f in dataclasses.fields(cls) if f.default is not dataclasses.MISSING]
    if defaults:
        raise TypeError(f"{cls.__name__}.{defaults[0]}: a params section field takes no default")
    cls.__pydantic_config__ = CONFIG
    cls.__get_pydantic_core_schema__ = classmethod(_section_schema)
    return cls


def _section_schema(cls: type, source: Any, handler: GetCoreSchemaHandler) -> CoreSchema:
    """The dataclass schema, taking a YAML mapping (strict mode would only take an instance; the fields
    stay strict), then the min/max order check."""
    schema = handler(source)
    handler.resolve_ref_schema(schema)["strict"] = False
    return core_schema.no_info_after_validator_function(_ranges_in_order, schema)


def _ranges_in_order(value: Any) -> Any:
    """A range given as two keys, ``min_<x>`` and ``max_<x>``, must not be empty."""
    for field in dataclasses.fields(value):
        low, upper = getattr(value, field.name), f"max_{field.name.removeprefix('min_')}"
        high = getattr(value, upper, None)
        numbers = all(isinstance(v, int | float) for v in (low, high))
        if field.name.startswith("min_") and numbers and low > high:
            raise PydanticCustomError("min_exceeds_max", "{field} exceeds {upper}",
                                      {"field": field.name, "value": low, "upper": upper, "high": high})
    return value


@dataclasses.dataclass(frozen=True)
class between:
    """A value (or each item of a list, or each value of a mapping) in [lo, hi]; lists of ``length``;
    ``ordered`` lists (a ``[min, max]`` range) must not decrease."""

    lo: float | None = None
    hi: float | None = None
    length: int | None = None
    ordered: bool = False

    def __get_pydantic_core_schema__(self, source: Any, handler: GetCoreSchemaHandler) -> CoreSchema:
        origin, args = get_origin(source), get_args(source)
        item = between(self.lo, self.hi)
        if origin is tuple:
            schema = handler.generate_schema(tuple[Annotated[args[0], item], ...])
            if self.ordered:
                schema = core_schema.no_info_after_validator_function(_in_order, schema)
            return core_schema.no_info_before_validator_function(self._of_length, schema)
        if origin is dict:
            return handler.generate_schema(dict[args[0], Annotated[args[1], item]])
        return core_schema.no_info_after_validator_function(self._in_range, handler(source))

    def allowed(self) -> str:
        """The range in words, for the error message."""
        if self.lo is not None and self.hi is not None:
            return f"between {self.lo} and {self.hi}"
        return f">= {self.lo}" if self.lo is not None else f"<= {self.hi}"

    def _of_length(self, value: Any) -> Any:
        """Before the items, as a wrong count is the first thing to fix (pydantic counts the valid items)."""
        if self.length is not None and isinstance(value, tuple) and len(value) != self.length:
            raise PydanticCustomError("list_length", "expected a list of {length} items", {"length": self.length})
        return value

    def _in_range(self, value: Any) -> Any:
        if (self.lo is not None and value < self.lo) or (self.hi is not None and value > self.hi):
            raise PydanticCustomError("out_of_range", "out of range, allowed {allowed}",
                                      {"value": value, "allowed": self.allowed()})
        return value


def _in_order(value: tuple) -> tuple:
    """A range given as one ``[min, max]`` list must not be empty."""
    if list(value) != sorted(value):
        raise PydanticCustomError("unordered", "give [min, max] with min <= max")
    return value
