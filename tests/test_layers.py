"""The import graph: layers one way, no cycles (imports inside functions included).

The layers and their order are those of shroud/__init__.py and CONTRIBUTING.md:
a module may import from its own layer or any layer below, never above.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]

# Lowest first. Builders share a layer; inside it only reference_fe -> meshes is allowed, and
# meshes -> reduced_model.airfoil (the loft takes the NACA profile from where the beam's sections
# take it: one definition, numpy only) and reduced_model.step_slices (the solid reads a STEP file as the
# beam's slices read it: one reader).
LAYERS = [
    ("base", ("shroud.base",)),
    ("core", ("shroud.core",)),
    ("params", ("shroud.params",)),
    ("analysis", ("shroud.analysis",)),
    ("api", ("shroud.api",)),
    ("builders", ("reduced_model", "meshes", "reference_fe")),
    ("studies", ("comparisons",)),
    ("app", ("workbench",)),
]
PACKAGES = ("shroud", "reduced_model", "meshes", "reference_fe", "comparisons", "workbench")
BUILDER_IMPORTS = {("reference_fe", "meshes")}      # the solid is built on the mesh package
BUILDER_MODULE_IMPORTS = {("meshes", "reduced_model.airfoil"), ("meshes", "reduced_model.step_slices")}


def layer_of(module: str) -> int | None:
    for rank, (_, prefixes) in enumerate(LAYERS):
        if any(module == p or module.startswith(p + ".") for p in prefixes):
            return rank
    return None


def module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def project_imports(path: Path) -> set[str]:
    """Project modules imported anywhere in ``path`` (top level or inside functions)."""
    me = module_name(path)
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            # "from pkg import mod" names a module when mod is one
            names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
        else:
            continue
        for name in names:
            if name.split(".")[0] in PACKAGES and _is_module(name) and name != me:
                found.add(name)
    return found


def _is_module(name: str) -> bool:
    base = ROOT.joinpath(*name.split("."))
    return base.with_suffix(".py").is_file() or (base / "__init__.py").is_file()


def graph() -> dict[str, set[str]]:
    files = [p for pkg in PACKAGES for p in (ROOT / pkg).rglob("*.py")]
    return {module_name(p): project_imports(p) for p in files}


def test_every_project_module_has_a_layer():
    missing = [m for m in graph() if m != "shroud" and layer_of(m) is None]
    assert not missing, f"modules outside every layer: {missing}"


def test_imports_go_down_the_layers():
    upward = []
    for importer, imported in graph().items():
        if importer == "shroud":
            continue
        for target in imported:
            a, b = layer_of(importer), layer_of(target)
            if b is None or b > a:
                upward.append(f"{importer} -> {target}")
            elif a == b == layer_of("reduced_model"):
                pair = (importer.split(".")[0], target.split(".")[0])
                if pair[0] != pair[1] and pair not in BUILDER_IMPORTS \
                        and (pair[0], target) not in BUILDER_MODULE_IMPORTS:
                    upward.append(f"{importer} -> {target} (builders are independent)")
    assert not upward, "imports against the layers:\n" + "\n".join(sorted(upward))


def test_no_import_cycles():
    """Strongly connected components of the module graph are single modules."""
    g = graph()
    index, low, stack, on, sccs, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in g.get(v, ()):
            if w not in g:
                continue
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
            sccs.append(comp)

    for v in g:
        if v not in index:
            visit(v)
    cycles = [sorted(c) for c in sccs if len(c) > 1]
    assert not cycles, f"import cycles: {cycles}"


def test_no_package_imports_one_that_imports_it_back():
    """At the level of top-level packages the graph has no loop either (shroud -> builders -> shroud)."""
    g = graph()
    pkg = {}
    for importer, imported in g.items():
        for target in imported:
            a, b = importer.split(".")[0], target.split(".")[0]
            if a != b:
                pkg.setdefault(a, set()).add(b)

    def reaches(a, b, seen=()):
        return any(n == b or (n not in seen and reaches(n, b, (*seen, n))) for n in pkg.get(a, ()))

    loops = sorted(f"{a} -> {b} -> ... -> {a}" for a in pkg for b in pkg[a] if reaches(b, a))
    assert not loops, loops


@pytest.mark.parametrize("layer", [name for name, _ in LAYERS])
def test_layer_table_matches_contributing(layer):
    """CONTRIBUTING.md names every layer of the graph the test holds."""
    assert f"`{layer}`" in (ROOT / "CONTRIBUTING.md").read_text()
