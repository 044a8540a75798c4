"""params.yaml: the one source of experiment parameters, loaded per profile and validated.

A leaf in params.yaml is either a plain value, used by every profile, or a mapping whose keys are
profile names (``{smoke: 2, default: 8, paper: 32}``); a profile missing there takes ``default``.
The typed schema lives beside this module (one dataclass per section); loading resolves the profile,
then checks every key, type and range against it and stops at the first problem with one line.
"""

from __future__ import annotations

import dataclasses
import functools
import math
import types
import typing
from pathlib import Path
from typing import Any

import yaml

from navlab.core.params.schema import PROFILES, Params

__all__ = ["PROFILES", "Params", "ParamsError", "load_params", "repo_root", "resolve_profile"]


class ParamsError(ValueError):
    """A params.yaml problem; the message is one line naming the key, the value and what is allowed."""


def repo_root() -> Path:
    """The checkout root: the nearest parent of the working directory (or of this file) with params.yaml."""
    for start in (Path.cwd(), Path(__file__).resolve()):
        for folder in (start, *start.parents):
            if (folder / "params.yaml").is_file():
                return folder
    raise ParamsError("params.yaml not found above the working directory; run from inside the navlab checkout")


def load_params(profile: str | None = None, path: str | Path | None = None) -> Params:
    """Read params.yaml, resolve ``profile`` (None: the file's own ``profile`` key) and validate it."""
    path = Path(path) if path is not None else repo_root() / "params.yaml"
    try:
        raw = yaml.load(path.read_text(), Loader=_UniqueKeyLoader)
    except FileNotFoundError:
        raise ParamsError(f"{path}: no such file; params.yaml must sit at the checkout root") from None
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        line = f" line {mark.line + 1}:" if mark is not None else ""
        problem = getattr(err, "problem", None) or str(err).splitlines()[0]
        raise ParamsError(f"{path}:{line} not valid YAML ({problem}); fix that line") from None
    if not isinstance(raw, dict):
        raise ParamsError(f"{path}: expected a mapping of sections at the top level")
    profile = profile if profile is not None else raw.get("profile", "default")
    if profile not in PROFILES:
        raise ParamsError(f"profile = {profile!r}: allowed profiles are {', '.join(PROFILES)}")
    resolved = resolve_profile(raw, profile)
    resolved["profile"] = profile
    return _build(Params, resolved, "")


class _UniqueKeyLoader(yaml.SafeLoader):
    """SafeLoader that refuses a repeated key (plain YAML lets the last one silently win)."""

    def construct_mapping(self, node, deep=False):
        seen = set()
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=deep)
            if key in seen:
                raise yaml.constructor.ConstructorError(
                    None, None, f"duplicate key {key!r} (the second would silently win); keep one",
                    key_node.start_mark)
            seen.add(key)
        return super().construct_mapping(node, deep)


def resolve_profile(tree: Any, profile: str, where: str = "") -> Any:
    """Replace every ``{smoke:…, default:…, paper:…}`` leaf by the value for ``profile``."""
    if isinstance(tree, dict):
        typos = sorted(set(map(str, tree)) - set(PROFILES))
        if tree and typos and set(tree) & set(PROFILES):
            raise ParamsError(f"{where or 'params.yaml'}: unknown profile {typos[0]!r} in a profile mapping; "
                              f"profiles are {', '.join(PROFILES)}")
        if tree and set(tree) <= set(PROFILES):
            if "default" not in tree:
                raise ParamsError(f"{where or 'params.yaml'} = {tree!r}: a profile mapping needs a 'default' value")
            return resolve_profile(tree.get(profile, tree["default"]), profile, where)
        return {k: resolve_profile(v, profile, f"{where}.{k}".lstrip(".")) for k, v in tree.items()}
    if isinstance(tree, list):
        return [resolve_profile(v, profile, f"{where}[{i}]") for i, v in enumerate(tree)]
    return tree


@functools.cache
def _hints(cls: type) -> dict[str, Any]:
    return typing.get_type_hints(cls)


def _build(cls: type, data: Any, where: str) -> Any:
    if not isinstance(data, dict):
        raise ParamsError(f"{where or 'params.yaml'} = {data!r}: expected a mapping of {cls.__name__} keys")
    fields = {f.name: f for f in dataclasses.fields(cls)}
    unknown = sorted(set(data) - set(fields))
    if unknown:
        key = f"{where}.{unknown[0]}".lstrip(".")
        raise ParamsError(f"{key}: unknown key; allowed keys here are {', '.join(sorted(fields))}")
    values = {}
    for name, field in fields.items():
        key = f"{where}.{name}".lstrip(".")
        if name not in data:
            raise ParamsError(f"{key}: missing; add it to params.yaml")
        values[name] = _check(_hints(cls)[name], data[name], key, field.metadata)
    for name, value in values.items():  # a range given as min_<x> / max_<x>: an empty one fails much later
        upper = f"max_{name.removeprefix('min_')}"
        numbers = all(isinstance(v, int | float) for v in (value, values.get(upper)))
        if name.startswith("min_") and upper in values and numbers and value > values[upper]:
            key = f"{where}.{name}".lstrip(".")
            raise ParamsError(f"{key} = {value!r} exceeds {upper} = {values[upper]!r}; give min <= max")
    return cls(**values)


def _check(hint: Any, value: Any, key: str, meta: typing.Mapping) -> Any:
    origin, args = typing.get_origin(hint), typing.get_args(hint)
    if dataclasses.is_dataclass(hint):
        return _build(hint, value, key)
    if origin in (typing.Union, types.UnionType):
        if value is None and type(None) in args:
            return None
        (inner,) = [a for a in args if a is not type(None)]
        return _check(inner, value, key, meta)
    if origin is typing.Literal:
        if value not in args:
            raise ParamsError(f"{key} = {value!r}: allowed values are {', '.join(map(repr, args))}")
        return value
    if origin in (tuple, list):
        item = args[0] if args else Any
        if not isinstance(value, list | tuple):
            raise ParamsError(f"{key} = {value!r}: expected a list")
        length = meta.get("length")
        if length is not None and len(value) != length:
            raise ParamsError(f"{key} = {value!r}: expected a list of {length} items")
        items = tuple(_check(item, v, f"{key}[{i}]", meta) for i, v in enumerate(value))
        if meta.get("ordered") and list(items) != sorted(items):
            raise ParamsError(f"{key} = {list(value)!r}: give [min, max] with min <= max")
        return items
    if origin is dict:
        if not isinstance(value, dict):
            raise ParamsError(f"{key} = {value!r}: expected a mapping")
        return {str(k): _check(args[1], v, f"{key}.{k}", meta) for k, v in value.items()}
    expected = {float: ((int, float), "a number"), int: (int, "an integer"), bool: (bool, "true or false"),
                str: (str, "a string")}.get(hint)
    if expected is not None:
        types_ok, words = expected
        if isinstance(value, dict):  # a leaf given as a mapping: a profile mapping with a mistyped profile
            raise ParamsError(f"{key} = {value!r}: expected {words}, or a profile mapping with keys "
                              f"{', '.join(PROFILES)} (unknown: {', '.join(map(str, value))})")
        if (isinstance(value, bool) and hint is not bool) or not isinstance(value, types_ok):
            raise ParamsError(f"{key} = {value!r}: expected {words}")
        if hint is float:
            value = float(value)
            if not math.isfinite(value):
                raise ParamsError(f"{key} = {value!r}: expected a finite number")
    lo, hi = meta.get("min"), meta.get("max")
    if (lo is not None and value < lo) or (hi is not None and value > hi):
        allowed = f"between {lo} and {hi}" if lo is not None and hi is not None else (
            f">= {lo}" if lo is not None else f"<= {hi}")
        raise ParamsError(f"{key} = {value!r}: out of range, allowed {allowed}")
    return value
