"""The package's architecture, read from its source: layers, import direction, module sizes.

Every import of every module under femslide/ counts - at module level, inside functions and under
``if TYPE_CHECKING`` - so that imports written inside functions cannot hide a cycle or a layer break.

Layers, lowest first; a module may import its own layer and the layers below it, never above:

    errors, version, records  <  elements  <  joints  <  model  <  results  <  analysis  <  output  <  scenes  <  app

``femslide/__init__.py`` (the public API) and ``__main__`` sit on top.  No module may be imported
from two sides of a cycle; no module is over 800 lines; no module runs code with effects outside
itself when imported (environment variables, threads, files).
"""
from __future__ import annotations

import ast
import os

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PKG = os.path.join(ROOT, "femslide")
LAYERS = [("errors", "version", "records"), ("elements",), ("joints",), ("model",), ("results",), ("analysis",),
          ("output",), ("scenes",), ("app",)]
TOP = {"femslide", "femslide.__main__"}
MAX_LINES = 800


def modules() -> dict:
    """{dotted module name: path} of every module of the package."""
    out = {}
    for d, _, files in os.walk(PKG):
        for f in files:
            if f.endswith(".py"):
                path = os.path.join(d, f)
                rel = os.path.relpath(path, ROOT)[:-3].replace(os.sep, ".")
                out[rel[:-len(".__init__")] if rel.endswith(".__init__") else rel] = path
    return out


def imports_of(name: str, path: str, known: set) -> set:
    """The femslide modules that ``name`` imports anywhere in its source (absolute or relative)."""
    tree = ast.parse(open(path, encoding="utf-8").read())
    pkg = name if path.endswith("__init__.py") else name.rpartition(".")[0]
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            targets = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = pkg
                for _ in range(node.level - 1):
                    base = base.rpartition(".")[0]
                mod = f"{base}.{node.module}" if node.module else base
            else:
                mod = node.module or ""
            # "from femslide.x import y": y may be a module of its own
            targets = [f"{mod}.{a.name}" if f"{mod}.{a.name}" in known else mod for a in node.names]
        else:
            continue
        for t in targets:
            while t and t not in known:
                t = t.rpartition(".")[0]
            if t and t.split(".")[0] == "femslide" and t != name:
                out.add(t)
    return out


GRAPH = None


def graph():
    global GRAPH
    if GRAPH is None:
        mods = modules()
        GRAPH = {m: imports_of(m, p, set(mods)) for m, p in mods.items()}
    return GRAPH


def layer(mod: str) -> int:
    if mod in TOP:
        return len(LAYERS)
    part = mod.split(".")[1]
    return next(i for i, names in enumerate(LAYERS) if part in names)


def test_every_module_belongs_to_a_layer():
    for m in graph():
        if m not in TOP:
            assert any(m.split(".")[1] in names for names in LAYERS), f"{m}: not in a layer {LAYERS}"


def test_imports_point_down_the_layers():
    bad = [f"{m} (layer {layer(m)}) imports {t} (layer {layer(t)})"
           for m, ts in graph().items() for t in sorted(ts) if t not in TOP and layer(t) > layer(m)]
    assert not bad, "\n".join(bad)


def test_nothing_imports_the_top():
    bad = [f"{m} imports {t}" for m, ts in graph().items() for t in ts if t in TOP and m not in TOP]
    assert not bad, "\n".join(bad)


def test_no_import_cycles():
    """Tarjan's strongly connected components of the module graph: every one a single module."""
    g = graph()
    index, low, stack, on, cycles = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in g[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                cycles.append(sorted(comp))

    for v in sorted(g):
        if v not in index:
            visit(v)
    assert not cycles, f"import cycles: {cycles}"


def test_subpackages_and_module_sizes():
    subs = {m.split(".")[1] for m in graph() if m.count(".") >= 2}
    assert len(subs) >= 4
    long = {m: n for m, p in modules().items() if (n := sum(1 for _ in open(p, encoding="utf-8"))) > MAX_LINES}
    assert not long, f"modules over {MAX_LINES} lines: {long}"


def _module_level_statements(tree):
    """Module-level statements, descending into if/try blocks (not into functions or classes)."""
    todo = list(tree.body)
    while todo:
        node = todo.pop(0)
        yield node
        if isinstance(node, ast.If) and "__name__" in ast.unparse(node.test):
            continue   # the script entry: runs only when executed, not when imported
        if isinstance(node, (ast.If, ast.Try)):
            todo[:0] = node.body + node.orelse + getattr(node, "handlers", []) + getattr(node, "finalbody", [])
        elif isinstance(node, ast.ExceptHandler):
            todo[:0] = node.body


@pytest.mark.parametrize("mod", sorted(modules()))
def test_no_import_time_side_effects(mod):
    """A module's top level only defines: imports, definitions, assignments of constants, docstrings.
    No call statement runs at import (e.g. setting an environment variable or loading a library),
    no assignment into os.environ."""
    tree = ast.parse(open(modules()[mod], encoding="utf-8").read())
    if mod == "femslide.__main__":
        return
    for node in _module_level_statements(tree):
        if isinstance(node, ast.If) and "__name__" in ast.unparse(node.test):
            continue
        if isinstance(node, ast.Expr) and isinstance(node.value, ast.Call):
            pytest.fail(f"{mod}:{node.lineno}: a call runs at import: {ast.unparse(node)[:80]}")
        if isinstance(node, (ast.Assign, ast.AugAssign)):
            for t in getattr(node, "targets", [getattr(node, "target", None)]):
                if isinstance(t, ast.Subscript) and "environ" in ast.unparse(t.value):
                    pytest.fail(f"{mod}:{node.lineno}: writes os.environ at import")
