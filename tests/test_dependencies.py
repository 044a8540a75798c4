"""pyproject.toml declares navlab's direct dependencies; environment.txt is their exact lock (issue 27).

Why: with only the lock, nobody can tell which of its ~200 packages navlab uses and which came along;
with only pyproject, an install would not be the one the reports were made with. So every third-party
package that lib/ imports must be declared, and every declared bound must be the version the lock pins.
"""

import ast
import re
import sys
import tomllib
from importlib.metadata import packages_distributions
from pathlib import Path

PROJECT = tomllib.loads(Path("pyproject.toml").read_text(encoding="utf8"))["project"]


def _name(dist: str) -> str:
    return re.sub(r"[-_.]+", "-", dist).lower()


def _requirements(*, extras: bool = True) -> dict[str, tuple[str, str]]:
    """{normalised name: (operator, version)} of the declared requirements, with or without the extras."""
    reqs = [*PROJECT["dependencies"],
            *(r for extra in PROJECT["optional-dependencies"].values() if extras for r in extra)]
    parsed = [re.fullmatch(r"([A-Za-z0-9_.\-]+)\s*(==|>=)\s*(\S+)", r) for r in reqs]
    assert all(parsed), [r for r, m in zip(reqs, parsed, strict=True) if not m]
    return {_name(m[1]): (m[2], m[3]) for m in parsed}


def _lock() -> dict[str, str]:
    lines = Path("environment.txt").read_text(encoding="utf8").splitlines()
    return {_name(a): b for a, _, b in (ln.partition("==") for ln in lines if "==" in ln and not ln.startswith("#"))}


def test_every_third_party_import_of_lib_is_declared():
    imported = set()
    for path in Path("lib").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf8"))):
            if isinstance(node, ast.Import):
                imported |= {a.name.split(".")[0] for a in node.names}
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                imported.add(node.module.split(".")[0])
    third_party = sorted(m for m in imported - set(sys.stdlib_module_names) if m != "navlab")
    declared = set(_requirements(extras=False))
    dists = packages_distributions()
    missing = [f"{m} ({', '.join(dists.get(m, ['not installed']))})" for m in third_party
               if not declared & {_name(d) for d in dists.get(m, [])}]
    assert not missing, "imported by lib/ but not in pyproject.toml's dependencies: " + ", ".join(missing)


def test_every_declared_bound_is_the_version_the_lock_pins():
    lock = _lock()
    wrong = [f"{name} {op}{version} (environment.txt: {lock.get(name, 'absent')})"
             for name, (op, version) in _requirements().items() if lock.get(name) != version]
    assert not wrong, "pyproject.toml and environment.txt disagree: " + "; ".join(wrong)
