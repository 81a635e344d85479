"""The package's modules import in one direction: no module imports one that imports it back,
and the trajectory's column names come from the compiled module alone."""

from __future__ import annotations

import ast
from pathlib import Path

import cushion
from cushion import _cushion

PACKAGE = Path(cushion.__file__).parent


def _module_name(path: Path) -> str:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _imports(path: Path) -> set[str]:
    """The package modules `path` imports, at any depth of its code (lazy imports count)."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level:
            base = package.split(".")
            base = base[: len(base) - node.level + 1]
            target = ".".join(base + ([node.module] if node.module else []))
            if node.module is None:
                out.update(f"{target}.{a.name}" for a in node.names)
            else:
                out.add(target)
        elif isinstance(node, ast.Import):
            out.update(a.name for a in node.names if a.name.startswith("cushion"))
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("cushion"):
            out.add(node.module)
    return out


def test_no_import_cycle():
    modules = {_module_name(p): p for p in PACKAGE.rglob("*.py")}
    graph = {m: {i for i in _imports(p) if i in modules and i != m} for m, p in modules.items()}

    # a package's __init__ re-exports its submodules; a cycle through it is one of submodules
    def reach(start: str) -> set[str]:
        seen, todo = set(), [start]
        while todo:
            for nxt in graph.get(todo.pop(), ()):
                if nxt not in seen and not (nxt != start and start.startswith(nxt + ".")):
                    seen.add(nxt)
                    todo.append(nxt)
        return seen

    cycles = [m for m in graph if m in reach(m) and not m.endswith("__main__")]
    assert not cycles, {m: sorted(graph[m]) for m in cycles}


def test_column_names_come_from_the_compiled_module():
    from cushion._run import COLUMNS

    assert COLUMNS is _cushion.COLUMNS
    assert COLUMNS == ("t", "x_r", "v_r", "x_t", "v_t", "x_p", "v_p", "s", "p1", "F_c", "F_r")
    run = cushion.simulate(trajectory=True)
    assert list(run.to_pandas().columns) == list(COLUMNS)
