"""Text that leaves the machine (an exported page) without the machine's folders in it.

``export`` embeds the plan's ``--explain`` text, which names the scene file and each model by the paths the scene
wrote (often absolute: ``/home/alice/work/model.glb``). A published page must not carry them (issue 28, item 2):
every absolute POSIX or Windows path keeps its file name only. Relative paths are what the author wrote and stay.
"""

from __future__ import annotations

import os
import re
from collections.abc import Iterable
from pathlib import Path

# the folders of an absolute path: "/a/b/" or "C:\a\b\" (not "linear/nearest", "1/2", "a.b/c", "x / y": the slash
# must start a token and be followed by a folder name); the file name after the last separator stays
ABSOLUTE_FOLDERS = re.compile(r"(?<![\w.~-])(?:[A-Za-z]:[\\/]|/)(?:[^\s'\"/\\:,;()\[\]]+[\\/])+")
HOME = re.compile(r"(?<![\w.])~[\w.-]*/(?:[^\s'\"/\\:,;()\[\]]+/)*")


def without_machine_paths(text: str, folders: Iterable[str | os.PathLike] = ()) -> str:
    """``text`` with the folders of every absolute path (and ``~/...``) removed: ``/tmp/x/scene.toml`` ->
    ``scene.toml``. ``folders`` (the scene's, its models', the home folder) are removed first as written, so that
    one with a space in its name goes as a whole."""
    known = {str(Path(f)) for f in folders if Path(f).is_absolute() and str(Path(f)) != Path(f).anchor}
    for folder in sorted(known, key=len, reverse=True):
        text = text.replace(folder + os.sep, "")
    return HOME.sub("", ABSOLUTE_FOLDERS.sub("", text))


def labels_without_machine_paths(calls: list, folders: Iterable[str | os.PathLike] = ()) -> list:
    """Recorded GPU calls with every ``label`` (which names the model file a buffer is for) made public; only
    labels: shader code and base64 data hold slashes that are not paths."""
    folders = list(folders)

    def clean(value):
        if isinstance(value, dict):
            return {k: without_machine_paths(v, folders) if k == "label" and isinstance(v, str) else clean(v)
                    for k, v in value.items()}
        if isinstance(value, list):
            return [clean(v) for v in value]
        return value

    return clean(calls)
