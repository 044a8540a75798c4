"""Code fingerprints: the sha256 of the navlab source a result was made by (docs/design.md, "Caches").

Why: a cache keyed on parameters alone outlives the code that made it (issue 13: an edited loss, HJ
dynamics or map generator left every cache "up to date"). Every "already built / resume" decision keys
on ``code_fingerprint(entry)`` beside its parameters and inputs.

The module set is derived, not listed by hand: starting from the entry module, every ``import`` /
``from ... import`` statement that names a navlab module (including imports inside functions, which
run when the code path does) is followed transitively, with the ``__init__`` of every package on the
way (importing ``navlab.a.b`` runs ``navlab/a/__init__.py``). Static, so the set does not depend on
what else a process happened to import. The same set tells a DVC stage which paths it depends on
(tests/test_pipeline.py).

Left out: the section declarations of params.yaml (``navlab.core.params.<section>``: field names, types
and ranges; they compute nothing). A result keys on the parameter *values* it reads, so a new field in
one section must not invalidate every other section's results (one PACER field re-solved every HJ grid,
~40 CPU-min). The loader (``navlab.core.params`` itself: profile resolution) stays in.
"""

from __future__ import annotations

import ast
import hashlib
from collections.abc import Iterable
from pathlib import Path

PACKAGE = "navlab"
LIB = Path(__file__).resolve().parents[2]  # the folder that holds navlab/

DECLARATIONS = "navlab.core.params."  # prefix of the modules left out (see above)

_IMPORTS: dict[tuple[Path, int, int], tuple[str, ...]] = {}  # (file, mtime_ns, size) -> imported names


def module_file(name: str, lib: Path | None = None) -> Path | None:
    """The source file of module ``name`` under ``lib`` (default: this checkout's lib/; a package's
    ``__init__.py``), or None."""
    base = (lib or LIB).joinpath(*name.split("."))
    for candidate in (base.with_suffix(".py"), base / "__init__.py"):
        if candidate.is_file():
            return candidate
    return None


def _imported_names(name: str, path: Path) -> tuple[str, ...]:
    """Every dotted name an import statement in ``path`` may load (``from a import b`` gives a and a.b)."""
    stat = path.stat()
    key = (path, stat.st_mtime_ns, stat.st_size)
    if key not in _IMPORTS:
        tree = ast.parse(path.read_bytes(), filename=str(path))
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        names: list[str] = []
        for node in ast.walk(tree):
            if isinstance(node, ast.Import):
                names += [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:  # relative: resolve against this module's package
                    parts = package.split(".")
                    base = ".".join(parts[: len(parts) - node.level + 1] + ([node.module] if node.module else []))
                else:
                    base = node.module or ""
                names.append(base)
                names += [f"{base}.{alias.name}" for alias in node.names if alias.name != "*"]
        _IMPORTS[key] = tuple(names)
    return _IMPORTS[key]


def imported_modules(*entries: str, lib: Path | None = None) -> dict[str, Path]:
    """navlab modules that ``entries`` load, transitively: {dotted name: source file}, sorted by name."""
    lib = lib or LIB
    found: dict[str, Path] = {}
    todo = list(entries)
    while todo:
        name = todo.pop()
        navlab = name == PACKAGE or name.startswith(PACKAGE + ".")
        if name in found or not navlab or name.startswith(DECLARATIONS):
            continue
        path = module_file(name, lib)
        if path is None:  # ``from navlab.x import some_function``: the name is not a module
            continue
        found[name] = path
        parts = name.split(".")
        todo += [".".join(parts[:i]) for i in range(1, len(parts))]  # parent packages' __init__
        todo += _imported_names(name, path)
    missing = [e for e in entries if e not in found]
    if missing:
        raise ValueError(f"{missing[0]}: no such navlab module under {lib}; pass a dotted module name "
                         "such as 'navlab.reach.precompute'")
    return dict(sorted(found.items()))


def source_fingerprint(files: Iterable[tuple[str, Path]]) -> str:
    """sha256 over (module name, source bytes) pairs in name order."""
    digest = hashlib.sha256()
    for name, path in sorted(files):
        digest.update(name.encode() + b"\0" + hashlib.sha256(path.read_bytes()).digest())
    return digest.hexdigest()


def code_fingerprint(*entries: str, lib: Path | None = None) -> str:
    """The fingerprint of the navlab source that ``entries`` (dotted module names) run."""
    return source_fingerprint(imported_modules(*entries, lib=lib).items())


def files_fingerprint(folder: str | Path) -> str:
    """sha256 over (relative path, content) of every file under ``folder``: the inputs a step reads."""
    folder = Path(folder)
    return source_fingerprint((p.relative_to(folder).as_posix(), p) for p in folder.rglob("*") if p.is_file())
