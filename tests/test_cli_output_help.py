"""Help and behaviour agree on output folders: a missing folder is made, a missing parent is refused ("create it
first", core/files/owned_files.py); a help text that says "made if missing" must say the parent must exist."""

from __future__ import annotations

import argparse

import pytest

from wgpurender.cli import build_parser
from wgpurender.core.errors import UserError
from wgpurender.core.files.owned_files import OwnedFolder


def _option_helps():
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    for name, parser in sub.choices.items():
        for action in parser._actions:
            yield name, action.option_strings, action.help or ""


def test_every_made_if_missing_help_says_the_parent_must_exist():
    said = [(name, opts, text) for name, opts, text in _option_helps() if "if missing" in text]
    assert said, "export -o says the folder is made if missing"  # the case this test is about is still there
    for name, opts, text in said:
        assert "parent" in text and "must exist" in text, (name, opts, text)


def test_the_folder_is_made_and_a_missing_parent_is_refused(tmp_path):
    OwnedFolder(tmp_path / "new", "test").finish()
    assert (tmp_path / "new").is_dir()
    with pytest.raises(UserError, match="create it first"):
        OwnedFolder(tmp_path / "missing" / "new", "test")
    assert not (tmp_path / "missing").exists()
