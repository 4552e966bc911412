"""No flag is parsed and then dropped: every (command, flag) is read by the command, or refused with one line.

The walk introspects the real parser (``wgpurender.cli.build_parser()``: every subcommand and sub-subcommand,
every action's ``dest``), nothing is listed by hand. The mechanical check chosen: static, over the source of the
function each parser runs (``func``) and every function it hands the parsed arguments to (called with ``args``,
in its own module or imported from another ``wgpurender`` module), collecting each ``args.<dest>`` read and each
``getattr(args, ...)`` (a name from a loop over a module constant counts for that constant's string keys).

A command that dispatches early on a flag (``if args.raw: return run_raw(args)``) has one *mode* per such
branch plus the rest, and every mode must read every flag: so ``demo --raw`` cannot drop ``--benchmark`` that
the wgpu window reads. The static check counts a read whatever follows it, so it proves "not parsed and then
never looked at", not "used well": the dynamic tests below check that the refusals are one line and exit 2, and
the uses issue 20 named (``demo --raw --benchmark/--validation/--anisotropy``) do what they say.
"""

from __future__ import annotations

import argparse
import ast
import importlib
import inspect
import os
import subprocess
import sys
import textwrap
from functools import cache
from pathlib import Path

import pytest

from wgpurender.cli import build_parser, main

REPO = Path(__file__).resolve().parent.parent
SKIP_ACTIONS = (argparse._HelpAction, argparse._VersionAction, argparse._SubParsersAction)


def leaf_parsers(parser: argparse.ArgumentParser | None = None, prefix: tuple[str, ...] = ()):
    """(command words, parser) for every parser that runs a command (has a ``func``), nested ones included."""
    parser = parser or build_parser()
    seen: set[int] = set()
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                if id(sub) in seen:
                    continue  # an alias
                seen.add(id(sub))
                if sub.get_default("func") is not None:
                    yield (*prefix, name), sub
                yield from leaf_parsers(sub, (*prefix, name))


def dests(parser: argparse.ArgumentParser) -> set[str]:
    return {a.dest for a in parser._actions if not isinstance(a, SKIP_ACTIONS) and a.dest != argparse.SUPPRESS}


@cache
def module_tree(name: str) -> tuple[ast.Module, dict[str, ast.FunctionDef], dict[str, ast.AST]]:
    """The module's AST, its top-level functions, and its top-level constants (name -> value node)."""
    tree = ast.parse(inspect.getsource(importlib.import_module(name)))
    functions = {n.name: n for n in tree.body if isinstance(n, ast.FunctionDef)}
    constants = {t.id: n.value for n in tree.body if isinstance(n, ast.Assign) for t in n.targets
                 if isinstance(t, ast.Name)}
    return tree, functions, constants


def imported_from(module: str, name: str) -> str | None:
    """The wgpurender module that ``name`` is imported from anywhere in ``module`` (function-level imports too)."""
    for node in ast.walk(module_tree(module)[0]):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("wgpurender"):
            if any((alias.asname or alias.name) == name for alias in node.names):
                return node.module
    return None


def strings_in(node: ast.AST) -> set[str]:
    return {n.value for n in ast.walk(node) if isinstance(n, ast.Constant) and isinstance(n.value, str)}


def reads(nodes: list[ast.AST], module: str, param: str, seen: set[tuple[str, str]]) -> set[str]:
    """Every attribute of ``param`` read in ``nodes`` or in the functions they hand ``param`` to."""
    out: set[str] = set()
    constants = module_tree(module)[2]
    for node in nodes:
        for sub in ast.walk(node):
            if isinstance(sub, ast.Attribute) and isinstance(sub.value, ast.Name) and sub.value.id == param:
                out.add(sub.attr)
            if not isinstance(sub, ast.Call):
                continue
            callee = sub.func.id if isinstance(sub.func, ast.Name) else None
            positions = [i for i, a in enumerate(sub.args) if isinstance(a, ast.Name) and a.id == param]
            if callee == "getattr" and positions == [0]:
                key = sub.args[1]
                if isinstance(key, ast.Constant):
                    out.add(key.value)
                else:  # a name from a loop: the string constants of the module constants the loop reads
                    names = {n.id for n in ast.walk(node) if isinstance(n, ast.Name)}
                    out |= set().union(*(strings_in(constants[n]) for n in names if n in constants))
            elif callee and positions:
                out |= reads_of_call(module, callee, positions[0], seen)
    return out


def reads_of_call(module: str, callee: str, position: int, seen: set[tuple[str, str]]) -> set[str]:
    target = module if callee in module_tree(module)[1] else imported_from(module, callee)
    if target is None or (target, callee) in seen or callee not in module_tree(target)[1]:
        return set()
    seen.add((target, callee))
    fn = module_tree(target)[1][callee]
    return reads(fn.body, target, fn.args.args[position].arg, seen)


def modes(func) -> dict[str, set[str]]:
    """The flags each mode of a command reads: one mode per early ``if args.X: ... return`` branch, and the rest."""
    module = func.__module__
    fn = module_tree(module)[1][func.__name__]
    param = fn.args.args[0].arg
    branches, rest = [], []
    for i, stmt in enumerate(fn.body):
        returns = isinstance(stmt, ast.If) and stmt.body and isinstance(stmt.body[-1], ast.Return)
        tested = returns and any(isinstance(n, ast.Attribute) and isinstance(n.value, ast.Name) and n.value.id == param
                                 for n in ast.walk(stmt.test))
        if tested:
            branches.append((ast.unparse(stmt.test), fn.body[:i] + [stmt.test] + stmt.body))
            rest.append(stmt.test)
        else:
            rest.append(stmt)
    out = {test: reads(body, module, param, set()) for test, body in branches}
    out["default"] = reads(rest, module, param, set())
    return out


def test_the_walk_sees_every_command():
    """The walk is not vacuous: it finds the commands and flags this test is about."""
    found = {" ".join(words): dests(p) for words, p in leaf_parsers()}
    assert {"render", "reference", "demo", "verify", "report", "bench perf", "bench accuracy"} <= set(found)
    assert {"anisotropy", "benchmark", "validation", "raw", "backend"} <= found["demo"]
    assert {"anisotropy", "size", "msaa", "format"} <= found["reference"]


def test_every_mode_of_every_command_reads_every_flag():
    dropped = []
    for words, parser in leaf_parsers():
        for mode, read in modes(parser.get_default("func")).items():
            for dest in sorted(dests(parser) - read):
                dropped.append(f"{' '.join(words)} [{mode}]: --{dest.replace('_', '-')} is parsed and never read")
    assert dropped == []


def test_the_check_catches_a_dropped_flag(tmp_path, monkeypatch):
    """An injected run() that reads one flag only in its default mode: the raw mode is reported."""
    (tmp_path / "flagwalk_injected.py").write_text(textwrap.dedent('''
        def run(args):
            if args.raw:
                return other(args)
            return args.benchmark

        def other(args):
            return args.size
    '''))
    monkeypatch.syspath_prepend(str(tmp_path))
    module = importlib.import_module("flagwalk_injected")
    try:
        assert modes(module.run) == {"args.raw": {"raw", "size"}, "default": {"raw", "benchmark"}}
    finally:
        del sys.modules["flagwalk_injected"]
        module_tree.cache_clear()


# -- what the reads do: refusals are one line and exit 2; the raw window's flags work -------------------------

@pytest.mark.parametrize(("argv", "says"), [
    (["demo", "--raw", "--backend", "Vulkan", "triangle"], "--backend"),
    (["demo", "--benchmark-runtime", "1", "triangle"], "--benchmark-runtime"),
    (["render", "triangle", "-o", "x.png", "--anisotropy", "scene"], "--anisotropy"),
    (["reference", "triangle", "-o", "x.png", "--anisotropy", "scene"], "--anisotropy"),
    (["demo", "triangle", "--anisotropy", "scene"], "--anisotropy"),
    (["bench", "perf", "--only", "frames", "--anisotropy", "scene"], "--anisotropy"),
    (["render", str(REPO / "assets" / "scenes" / "unlit.toml"), "-o", "x.png", "--time", "2"], "--time"),
    (["demo", "--raw", str(REPO / "assets" / "scenes" / "unlit.toml"), "--time", "2"], "--time"),
    (["demo", "--raw", "triangle", "--anisotropy", "scene"], "--anisotropy"),
    (["verify", "--anisotropy", "scene"], "--anisotropy"),
    (["verify", "--size", "64x48"], "--size"),
    (["render", "triangle", "-o", "x.png", "--raw"], "--raw"),
    (["bench", "accuracy", str(REPO / "assets" / "scenes" / "final.toml"), "--truth", "analytic", "--knob", "msaa"],
     "--knob"),
])
def test_a_flag_that_cannot_apply_is_refused_with_one_line(capsys, tmp_path, monkeypatch, argv, says):
    monkeypatch.chdir(tmp_path)
    code = main(argv)
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "error" in err and says in err, err
    assert not list(tmp_path.iterdir())  # nothing written, no window opened


from xvfb import xvfb_display  # noqa: E402,F401 - the shared Xvfb fixture "display"


def raw_demo(display, *args):
    env = dict(os.environ, DISPLAY=display)
    return subprocess.run([sys.executable, "-m", "wgpurender", "demo", "--raw", *args], env=env, cwd=REPO,
                          capture_output=True, text=True, timeout=300)


def test_raw_demo_benchmark_writes_the_wgpu_windows_csv(display, tmp_path):
    csv = tmp_path / "bench.csv"
    result = raw_demo(display, "triangle", "--size", "64x48", "--benchmark", "--benchmark-warmup", "0.2",
                      "--benchmark-runtime", "0.3", "--benchmark-result-file", str(csv))
    assert result.returncode == 0, result.stderr
    rows = csv.read_text().splitlines()
    assert rows[0] == "frame,frame_ms" and len(rows) >= 2
    times = [float(r.split(",")[1]) for r in rows[1:]]
    assert all(t > 0 for t in times) and [int(r.split(",")[0]) for r in rows[1:]] == list(range(len(times)))
    assert sum(times) >= 300 and f"wrote {csv}" in result.stdout and "benchmark:" in result.stdout


def test_raw_demo_validation_counts_messages_or_refuses(display):
    result = raw_demo(display, "triangle", "--size", "64x48", "--frames", "2", "--validation")
    if result.returncode == 2:  # no validation layer here: one line says so
        assert result.stderr.count("\n") == 1 and "validation" in result.stderr, result.stderr
    else:
        assert result.returncode == 0, result.stderr
        assert "validation messages: 0" in result.stdout


def test_raw_demo_anisotropy_reaches_the_raw_plan(display, tmp_path):
    """--anisotropy scene vs the default: each screenshot equals the offscreen raw render of that rule."""
    from wgpurender.core.files.imageio import load_png
    from wgpurender.raw_path import render_reference

    scene = str(REPO / "assets" / "scenes" / "brick.toml")
    shots = {}
    for rule in ("auto", "scene"):
        shots[rule] = tmp_path / f"{rule}.png"
        result = raw_demo(display, scene, "--size", "96x72", "--frames", "2", "--time", "0", "--anisotropy", rule,
                          "--screenshot", str(shots[rule]))
        assert result.returncode == 0, result.stderr
    for rule, shot in shots.items():
        want = render_reference(scene, (96, 72), anisotropy=rule)
        assert (load_png(shot) == want).all(), rule
    from wgpurender.core.plan import resolve_plan
    from wgpurender.raw_path.device.context import get_vulkan

    facts = get_vulkan().adapter_facts()
    if facts.adapter_type == "CPU":  # the rule changes the sampler here, so the two images must differ
        assert [s.spec.max_anisotropy for s in resolve_plan(scene, facts, anisotropy="auto").samplers] == [1]
        assert not (load_png(shots["auto"]) == load_png(shots["scene"])).all()
