"""README.md is a front page (the two set-up commands, one picture and a ten-line tour within 40 lines), every
flag the CLI has is in the command summary of docs/guide.md, the top-level --help names every bench suite, and
the relative links of the front page, the docs index and the guide point at files that exist."""

from __future__ import annotations

import argparse
import re
from pathlib import Path

from wgpurender.cli import build_parser

REPO = Path(__file__).resolve().parent.parent
README = REPO / "README.md"
GUIDE = REPO / "docs" / "guide.md"


def _flags(parser: argparse.ArgumentParser, prefix: tuple[str, ...] = ()) -> list[tuple[str, list[str]]]:
    """(command, the option's spellings) for every visible option of every (sub)command."""
    out = []
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                out += _flags(sub, (*prefix, name))
        elif action.option_strings and action.help != argparse.SUPPRESS and "--help" not in action.option_strings:
            out.append((" ".join(prefix), list(action.option_strings)))
    return out


def test_the_readme_opens_with_set_up_a_picture_and_a_tour():
    head = README.read_text().splitlines()[:40]
    commands = [line.split("#")[0].strip() for line in head if line.startswith("make ")]
    assert commands[:2] == ["make demo", "make test"], "the two set-up commands come first"
    assert head.index(next(x for x in head if x.startswith("make demo"))) < 5
    pictures = [x for x in head if x.startswith("![")]
    assert len(pictures) == 1 and (REPO / re.search(r"\]\(([^)]+)\)", pictures[0]).group(1)).is_file()
    said = head.index(next(x for x in head if "tour" in x.lower()))
    start = head.index("```sh", said) + 1
    tour = head[start:head.index("```", start)]
    assert len(tour) == 10 and all(x.startswith(("wgpurender ", "python ")) for x in tour), tour


def test_every_flag_is_in_the_command_summary():
    text = GUIDE.read_text()
    summary = text[text.index("## The command line"):]
    summary = summary[summary.index("```sh"):summary.index("```\n", summary.index("```sh") + 5)]
    missing = [f"{cmd} {flags[-1]}" for cmd, flags in _flags(build_parser())
               if not any(re.search(rf"(?<![\w-]){re.escape(flag)}(?![\w-])", summary) for flag in flags)]
    assert not missing, f"flags missing from docs/guide.md's command summary: {missing}"
    for cmd in build_parser()._subparsers._group_actions[0].choices:
        assert f"wgpurender {cmd}" in summary, cmd


def test_top_level_help_lists_every_bench_suite():
    parser = build_parser()
    commands = parser._subparsers._group_actions[0]
    bench = commands.choices["bench"]
    suites = bench._subparsers._group_actions[0].choices
    help_text = parser.format_help()
    for suite in suites:
        assert re.search(rf"\b{re.escape(suite)}\b", help_text.split("bench", 1)[1]), suite


def test_demo_present_mode_offers_what_the_wgpu_window_can_do():
    demo = build_parser()._subparsers._group_actions[0].choices["demo"]
    text = demo.format_help()
    assert "--present-mode fifo|immediate" in text and "mailbox only with --raw" in " ".join(text.split())


def test_relative_links_resolve():
    """The front page, the docs index and the guide (docs/verification.md links into a run's output on purpose)."""
    for page in (README, REPO / "docs" / "README.md", GUIDE):
        for target in re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", page.read_text()):
            if re.match(r"[a-z]+://", target):
                continue
            assert (page.parent / target).exists(), f"{page.relative_to(REPO)}: {target} does not exist"
