"""The design's layer list is the import rule: a navlab package imports only from its own layer and below.

Why a test: the list is what a new maintainer reads first (docs/design.md, "Layers: the import rule"), and
an upward import (a low layer reaching for the pipeline or the CLI) is how layering quietly erodes; the test
reads the list from docs/design.md itself, so the list and the code cannot drift apart.
"""

import ast
import re
from pathlib import Path

LIB = Path("lib/navlab")
DESIGN = Path("docs/design.md")


def design_layers() -> dict[str, int]:
    """{package: rank} from the design's `core → maps → … → cli` line; packages in braces share a rank."""
    line = next(ln for ln in DESIGN.read_text(encoding="utf8").splitlines() if ln.startswith("core → "))
    return {name.strip(): rank for rank, layer in enumerate(line.split(" → "))
            for name in layer.strip("{} ").split(",")}


def navlab_imports(path: Path) -> set[str]:
    """The navlab packages one module imports (``navlab.<package>...``), function-level imports included."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf8"))):
        names = [a.name for a in node.names] if isinstance(node, ast.Import) else \
            [node.module] if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module else []
        found |= {m.split(".")[1] for m in names if re.match(r"navlab\.\w", m)}
    return found


def test_every_package_is_in_the_design_layer_list():
    packages = {p.name for p in LIB.iterdir() if (p / "__init__.py").is_file()} | {"cli"}
    assert packages == set(design_layers()), "update docs/design.md's layer list (Layers)"


def test_no_package_imports_a_higher_or_sibling_layer():
    rank = design_layers()
    upward = []
    for path in sorted(LIB.rglob("*.py")):
        parts = path.relative_to(LIB).parts
        if len(parts) == 1 and path.stem != "cli":
            continue  # navlab/__init__.py and __main__.py sit above everything
        me = parts[0].removesuffix(".py")
        upward += [f"{path} imports navlab.{m}" for m in navlab_imports(path)
                   if m in rank and m != me and rank[m] >= rank[me]]
    assert not upward, "imports against the layer list in docs/design.md:\n" + "\n".join(upward)
