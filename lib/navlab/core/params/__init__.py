"""params.yaml: the one source of experiment parameters, loaded per profile and validated.

A leaf in params.yaml is either a plain value, used by every profile, or a mapping whose keys are
profile names (``{smoke: 2, default: 8, paper: 32}``); a profile missing there takes ``default``.
The typed schema lives beside this module (one dataclass per section); loading resolves the profile,
then pydantic checks every key, type and range against it; the first problem stops it with one line.
"""

from __future__ import annotations

import dataclasses
import functools
import typing
from pathlib import Path
from typing import Any

import yaml
from pydantic import TypeAdapter, ValidationError

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
    return _validate(resolved)


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


def _validate(data: dict[str, Any]) -> Params:
    """The typed ``Params`` of a resolved profile, or a one-line ParamsError for its first problem."""
    try:
        return _adapter().validate_python(_yaml_values(data))
    except ValidationError as err:
        raise _params_error(_first_problem(err.errors())) from None


def _first_problem(errors: list[Any]) -> Any:
    """pydantic's first error, or an unknown key of a section holding it: a misspelt key is both unknown and
    missing, and its name is the one to fix."""
    first = errors[0]["loc"]
    unknown = [e for e in errors
               if e["type"] == "unexpected_keyword_argument" and first[:len(e["loc"]) - 1] == e["loc"][:-1]]
    return min(unknown, key=lambda e: len(e["loc"]), default=errors[0])


@functools.cache
def _adapter() -> TypeAdapter[Params]:
    """Built on first use, once: the schema takes a moment to build and most imports never load params."""
    return TypeAdapter(Params)


def _yaml_values(tree: Any) -> Any:
    """YAML spells a tuple as a list (the schemas hold tuples: hashable, immutable) and may key a mapping
    by a number; strict validation wants tuples and string keys."""
    if isinstance(tree, dict):
        return {str(k): _yaml_values(v) for k, v in tree.items()}
    if isinstance(tree, list):
        return tuple(_yaml_values(v) for v in tree)
    return tree


def _shown(value: Any) -> Any:
    """``value`` as params.yaml spells it (lists, not the tuples validation saw), for a message."""
    if isinstance(value, dict):
        return {k: _shown(v) for k, v in value.items()}
    return [_shown(v) for v in value] if isinstance(value, tuple) else value


_EXPECTED = {"float_type": "a number", "int_type": "an integer", "bool_type": "true or false",
             "string_type": "a string", "tuple_type": "a list", "dict_type": "a mapping"}


def _params_error(error: Any) -> ParamsError:
    """One line for pydantic's first error: the dotted key, the value and what is allowed."""
    kind, loc, ctx = error["type"], error["loc"], error.get("ctx") or {}
    if kind == "value_error" and isinstance(ctx.get("error"), ParamsError):  # Params.__post_init__: constraints.py
        return ctx["error"]
    key = "".join(f"[{part}]" if isinstance(part, int) else f".{part}" for part in loc).lstrip(".")
    value = _shown(ctx.get("value", error["input"]))
    if kind == "missing":
        return ParamsError(f"{key}: missing; add it to params.yaml")
    if kind == "unexpected_keyword_argument":
        allowed = ", ".join(sorted(f.name for f in dataclasses.fields(_section_at(loc[:-1]))))
        return ParamsError(f"{key}: unknown key; allowed keys here are {allowed}")
    if kind == "min_exceeds_max":
        key = f"{key}.{ctx['field']}".lstrip(".")
        return ParamsError(f"{key} = {value!r} exceeds {ctx['upper']} = {ctx['high']!r}; give min <= max")
    if kind == "dataclass_type":
        return ParamsError(f"{key or 'params.yaml'} = {value!r}: expected a mapping of {ctx['class_name']} keys")
    if kind in ("float_type", "int_type", "bool_type", "string_type") and isinstance(value, dict):
        return ParamsError(f"{key} = {value!r}: expected {_EXPECTED[kind]}, or a profile mapping with keys "
                           f"{', '.join(PROFILES)} (unknown: {', '.join(map(str, value))})")
    what = {"literal_error": f"allowed values are {ctx.get('expected')}", "finite_number": "expected a finite number",
            **{k: f"expected {words}" for k, words in _EXPECTED.items()}}.get(kind, error["msg"])
    return ParamsError(f"{key} = {value!r}: {what}")


def _section_at(loc: tuple) -> type:
    """The section class at ``loc`` (a path of field names from the root)."""
    cls: Any = Params
    for name in loc:
        cls = typing.get_type_hints(cls)[name]
    return cls
