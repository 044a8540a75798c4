"""What each DVC stage runs: the navlab modules behind a stage's command, and the deps that must cover them.

Why: a stage whose deps miss a module it runs is not re-run when that module changes, and DVC records
an old result under new code (issue 13). The module set is the one the caches key on
(``navlab.core.fingerprint.imported_modules``), started from the stage's entry point:

- ``notebook run NB``: the navlab modules NB's code cells import;
- ``artifacts build --only NAME``: the module that defines the artefact step NAME;
- ``data build``: the modules of the data-build steps and the build itself (``navlab.pipeline.dataset``);
- ``reports index``: the report writer and each paper's claims registry.

Convention for a new stage: its ``deps`` list every file this returns, or a folder that holds them
(``lib/navlab/pacer`` covers all of pacer); ``tests/test_pipeline.py`` names any path missing.
"""

from __future__ import annotations

import ast
import json
import shlex
from pathlib import Path

from navlab.core.fingerprint import imported_modules, module_file


def notebook_imports(notebook: str | Path) -> list[str]:
    """The navlab modules that a notebook's code cells import (IPython magics skipped)."""
    cells = json.loads(Path(notebook).read_text(encoding="utf8"))["cells"]
    names: set[str] = set()
    for cell in cells:
        if cell.get("cell_type") != "code":
            continue
        source = "".join(cell["source"])
        source = "\n".join(line for line in source.splitlines() if not line.lstrip().startswith(("%", "!")))
        for node in ast.walk(ast.parse(source)):
            if isinstance(node, ast.Import):
                names |= {a.name for a in node.names}
            elif isinstance(node, ast.ImportFrom) and node.module:
                names |= {node.module} | {f"{node.module}.{a.name}" for a in node.names}
    return sorted(n for n in names if n.split(".")[0] == "navlab" and module_file(n) is not None)


def entry_modules(cmd: str, root: str | Path) -> list[str]:
    """The navlab modules a stage command starts from (see the module docstring)."""
    from navlab.pipeline.steps import artifact_steps, data_steps

    args = shlex.split(cmd)
    if args[:3] != ["python", "-m", "navlab"]:
        raise ValueError(f"stage command {cmd!r}: navlab stages run `python -m navlab ...`")
    group, sub = args[3:5]
    if (group, sub) == ("notebook", "run"):
        return notebook_imports(Path(root, args[5]))
    if (group, sub) == ("artifacts", "build"):
        steps = dict(artifact_steps())
        return sorted({steps[name].__module__ for name in args[args.index("--only") + 1:: 2]})
    if (group, sub) == ("data", "build"):
        return sorted({fn.__module__ for _, fn in data_steps()} | {"navlab.pipeline.dataset"})
    if (group, sub) == ("reports", "index"):
        from navlab.pipeline.results import claim_modules

        return ["navlab.pipeline.results", *claim_modules().values()]
    raise ValueError(f"stage command {cmd!r}: no entry point known for `{group} {sub}`; add it to "
                     "navlab.pipeline.stages.entry_modules")


def stage_sources(cmd: str, root: str | Path) -> list[str]:
    """Repository-relative paths of every navlab source file the stage command runs."""
    root = Path(root).resolve()
    modules = imported_modules(*entry_modules(cmd, root), lib=root / "lib")
    return sorted(path.resolve().relative_to(root).as_posix() for path in modules.values())
