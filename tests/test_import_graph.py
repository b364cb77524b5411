"""The import graph of `src/usvsim`, read with `ast` (nothing is imported): no cycles (type-only imports
included), and the engine layers never import the I/O layers (bridges, CLI, viewer)."""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src"


def module_name(path: Path) -> str:
    parts = list(path.relative_to(SRC).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _is_type_checking(node: ast.If) -> bool:
    test = node.test
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _imports(tree: ast.AST, modules: set[str], package: str):
    """(imported module, type_only) for every import statement in `tree`, at any depth."""
    type_only_nodes = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and _is_type_checking(node):
            type_only_nodes.update(id(n) for stmt in node.body for n in ast.walk(stmt))
    for node in ast.walk(tree):
        names: list[str] = []
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(package.split(".")[: len(package.split(".")) - node.level + 1] + [base]).strip(".")
            names = [f"{base}.{a.name}" if f"{base}.{a.name}" in modules else base for a in node.names]
        for name in names:
            while name and name not in modules:
                name = name.rpartition(".")[0]
            if name:
                yield name, id(node) in type_only_nodes


def import_graph() -> dict[str, dict[str, bool]]:
    """module → {imported module: type_only} (type_only False if any import of it is at runtime)."""
    files = {module_name(p): p for p in (SRC / "usvsim").rglob("*.py")}
    modules = set(files)
    graph: dict[str, dict[str, bool]] = {}
    for name, path in files.items():
        package = name if path.name == "__init__.py" else name.rpartition(".")[0]
        edges: dict[str, bool] = {}
        for target, type_only in _imports(ast.parse(path.read_text()), modules, package):
            if target != name:
                edges[target] = edges.get(target, True) and type_only
        graph[name] = edges
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                out.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


# the engine (the simulation and everything under it) knows nothing of the I/O layers above it
ENGINE = ("core", "messages", "config", "ocean", "hydro", "vessels", "vessel", "world", "sensors", "control",
          "ground_truth", "commands", "simulation")  # fmt: skip
IO_LAYERS = ("bridges", "cli", "viewer")


def _package(module: str) -> str:
    return module.split(".")[1] if "." in module else ""


def test_no_import_cycles_counting_type_only_imports():
    """The root package's lazy re-exports (`usvsim.Simulation`) are a facade over the tree, not a layer."""
    graph = {m: set(edges) for m, edges in import_graph().items() if m != "usvsim"}
    assert cycles(graph) == []


def test_the_engine_never_imports_bridges_cli_or_viewer():
    bad = [f"{m} -> {t}" for m, edges in import_graph().items() for t in edges
           if _package(m) in ENGINE and _package(t) in IO_LAYERS]  # fmt: skip
    assert bad == []


def test_the_graph_is_read():
    """Guards the reader itself: known edges are found, type-only ones marked so."""
    graph = import_graph()
    assert graph["usvsim.simulation"]["usvsim.world.world"] is False
    assert graph["usvsim.sensors.base"]["usvsim.world.world"] is True
    assert "usvsim.core.queues" in graph["usvsim.commands"]
