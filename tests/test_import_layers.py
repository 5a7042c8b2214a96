"""No import circle among ship_env's modules, the imports under ``TYPE_CHECKING`` included.

A circle that only type checking keeps from failing at run time still ties the modules together:
neither can be read, tested or moved without the other. The imports are read with ``ast`` from the
source (nothing is imported), each resolved to the module it names (a package is its ``__init__``;
``from package import name`` is the submodule where ``name`` is one). An import inside a function
is left out: it runs when the function is called, the command line's way of loading a command's
libraries only for that command.

The workbench's stages (its subpackages) import one way too: each only from the stages before it,
imports inside functions included (:data:`WORKBENCH_STAGES`).
"""

from __future__ import annotations

import ast
from pathlib import Path

import ship_env

ROOT = Path(ship_env.__file__).parent


def module_name(path: Path) -> str:
    parts = path.relative_to(ROOT.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def module_level(node: ast.AST, in_functions: bool = False) -> list[ast.AST]:
    """The statements of ``node`` outside function bodies (in classes, ``if`` and ``try`` blocks too),
    or, ``in_functions``, all of them."""
    found = []
    for child in ast.iter_child_nodes(node):
        if in_functions or not isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.Lambda)):
            found += [child, *module_level(child, in_functions)]
    return found


def imported(tree: ast.Module, name: str, is_package: bool, modules: set[str], in_functions: bool = False) -> set[str]:
    """The ship_env modules that a module's imports outside functions (or, ``in_functions``, anywhere) name."""
    package = name if is_package else name.rpartition(".")[0]
    found: set[str] = set()
    for node in module_level(tree, in_functions):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            base = package.split(".")[: len(package.split(".")) - node.level + 1] if node.level else []
            source = ".".join([*base, node.module] if node.module else base)
            found.update(
                f"{source}.{alias.name}" if f"{source}.{alias.name}" in modules else source for alias in node.names
            )
    return {module for module in found if module in modules and module != name}


def import_graph(in_functions: bool = False) -> dict[str, set[str]]:
    paths = {module_name(path): path for path in ROOT.rglob("*.py")}
    return {
        name: imported(ast.parse(path.read_text()), name, path.name == "__init__.py", set(paths), in_functions)
        for name, path in paths.items()
    }


def circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The graph's strongly connected components of more than one module (Tarjan's algorithm)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for target in sorted(graph[node]):
            if target not in index:
                visit(target)
                low[node] = min(low[node], low[target])
            elif target in on_stack:
                low[node] = min(low[node], index[target])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return found


def test_the_circle_finder_finds_a_circle_through_a_type_checking_import():
    source = "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from ship_env.b import B\n"
    modules = {"ship_env.a", "ship_env.b", "ship_env.c"}
    graph = {
        "ship_env.a": imported(ast.parse(source), "ship_env.a", False, modules),
        "ship_env.b": imported(
            ast.parse("try:\n    from . import c\nexcept ImportError:\n    pass\n"), "ship_env.b", False, modules
        ),
        "ship_env.c": imported(ast.parse("import ship_env.a\n"), "ship_env.c", False, modules),
    }
    assert circles(graph) == [["ship_env.a", "ship_env.b", "ship_env.c"]]
    graph["ship_env.b"] = imported(ast.parse("def f():\n    from . import c\n"), "ship_env.b", False, modules)
    assert circles(graph) == []


def test_no_import_circle_among_ship_env_modules():
    assert circles(import_graph()) == []


#: The workbench's stages, in the order a log goes through them. A stage's modules import only from
#: its own stage and those before it, from :data:`WORKBENCH_SHARED` and from outside the workbench;
#: the workbench's package and its command modules (``cli``, ``cli_fit``, ...) import from every stage.
WORKBENCH_STAGES = ("logs", "fitting", "judging", "deciding", "reporting", "synthetic")
#: The workbench's modules beside its stages that every stage may import; they import no other.
WORKBENCH_SHARED = ("defaults", "outputs")


def workbench_layer(module: str) -> int | None:
    """A workbench module's layer: 0 for the shared modules, 1 for the first stage and so on; None for
    the workbench's package, its commands, and modules outside the workbench."""
    parts = module.split(".")
    if parts[:2] != ["ship_env", "workbench"] or len(parts) < 3:
        return None
    if parts[2] in WORKBENCH_SHARED:
        return 0
    if parts[2] in WORKBENCH_STAGES:
        return 1 + WORKBENCH_STAGES.index(parts[2])
    return None


def upward_imports(graph: dict[str, set[str]]) -> list[tuple[str, str]]:
    """Each (module, imported) where a stage's module (or a shared one) imports a workbench module of a
    later stage, or one outside the stages (the workbench's package, a command module)."""
    found = []
    for module, targets in sorted(graph.items()):
        layer = workbench_layer(module)
        if layer is None:
            continue
        for target in sorted(targets):
            if not target.startswith("ship_env.workbench"):
                continue
            allowed = workbench_layer(target)
            if allowed is None or allowed > layer or (layer == 0 and allowed != 0):
                found.append((module, target))
    return found


def test_the_layer_check_finds_an_import_of_a_later_stage_or_a_command():
    graph = {
        "ship_env.workbench.fitting.fit": {"ship_env.workbench.logs.logs", "ship_env.workbench.defaults"},
        "ship_env.workbench.fitting.replay": {"ship_env.workbench.judging.bands", "ship_env.model"},
        "ship_env.workbench.judging.bands": {"ship_env.workbench.fitting", "ship_env.workbench.judging.validation"},
        "ship_env.workbench.reporting.tables": {"ship_env.workbench.cli", "ship_env.workbench"},
        "ship_env.workbench.outputs": {"ship_env.workbench.logs.logs"},
        "ship_env.workbench.cli": {"ship_env.workbench.synthetic.demo_logs"},
    }
    assert upward_imports(graph) == [
        ("ship_env.workbench.fitting.replay", "ship_env.workbench.judging.bands"),
        ("ship_env.workbench.outputs", "ship_env.workbench.logs.logs"),
        ("ship_env.workbench.reporting.tables", "ship_env.workbench"),
        ("ship_env.workbench.reporting.tables", "ship_env.workbench.cli"),
    ]


def test_each_workbench_stage_imports_only_from_the_stages_before_it():
    graph = import_graph(in_functions=True)
    stages = {module.split(".")[2] for module in graph if workbench_layer(module)}
    assert stages == set(WORKBENCH_STAGES)  # every stage is a subpackage, and is checked
    workbench = {module for module in graph if module.startswith("ship_env.workbench.")}
    assert {module for module in workbench if workbench_layer(module) is None} == {
        f"ship_env.workbench.{name}"
        for name in ("cli", "cli_compare", "cli_diagnose", "cli_fit", "cli_fit_mmg", "cli_improve")
    }  # each of the others is in a stage or shared
    assert upward_imports(graph) == []
