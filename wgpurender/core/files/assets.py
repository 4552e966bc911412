"""Where the course's data is: the scenes, models, textures and reference images of ``assets/``, and the notebook.

The repository keeps them at the top level (``assets/``, ``examples/``), beside the package. A wheel carries
copies in ``wgpurender/_assets`` and ``wgpurender/_examples`` (setup.py's build hook puts them there, as it does
the shaders); an editable install or a plain checkout reads the top-level folders.

A bundled scene is found by name (``final`` is ``assets/scenes/final.toml``) and by its repository path
(``assets/scenes/final.toml``) from any folder: a file that exists where the user points always wins.
API-free (no wgpu, no vulkan).
"""

from __future__ import annotations

import os
from importlib import resources
from pathlib import Path, PurePath

CHECKOUT = Path(__file__).resolve().parents[3]
# repository folder -> folder inside the package
PACKAGED = {"assets": "_assets", "examples": "_examples"}
SCENE_SUFFIX = ".toml"


def _folder(name: str) -> Path:
    """The wheel's copy of the repository folder ``name`` if it exists, else the checkout's."""
    try:
        packaged = Path(str(resources.files("wgpurender") / PACKAGED[name]))
    except ModuleNotFoundError:  # pragma: no cover - the package is importing itself
        packaged = None
    return packaged if packaged is not None and packaged.is_dir() else CHECKOUT / name


def assets_dir() -> Path:
    """``assets/``: models, textures, scenes and the reference images."""
    return _folder("assets")


def scene_dir() -> Path:
    return assets_dir() / "scenes"


def reference_dir() -> Path:
    """The committed reference images and their tolerance table."""
    return assets_dir() / "reference"


def notebook_path() -> Path:
    """The course tour notebook (examples/course_tour.ipynb)."""
    return _folder("examples") / "course_tour.ipynb"


def bundled_scene_names() -> list[str]:
    """The scenes that ship with the course, by name (``wgpurender render final``)."""
    return sorted(p.stem for p in scene_dir().glob(f"*{SCENE_SUFFIX}"))


def absent_files(scene: Path) -> list[str]:
    """The files a scene names (``path``, ``*_map``) that are not there, as written: the tutorial scenes name the
    tutorial's model and texture beside the repository (../shared/anchors), which a wheel never has."""
    import tomllib

    names: list[str] = []

    def walk(node) -> None:
        if isinstance(node, dict):
            for key, value in node.items():
                if isinstance(value, str) and (key == "path" or key.endswith("_map")):
                    names.append(value)
                else:
                    walk(value)
        elif isinstance(node, list):
            for item in node:
                walk(item)

    walk(tomllib.loads(scene.read_text(encoding="utf-8")))
    return [name for name in names if not (scene.parent / name).is_file()]


def bundled_scene(target: str | PurePath) -> Path | None:
    """The bundled scene ``target`` names: ``final``, ``final.toml`` or ``assets/scenes/final.toml``; else None."""
    text = str(target)
    if not text or "\x00" in text:
        return None
    parts = PurePath(text).parts
    if len(parts) > 1 and parts[0] == "assets":  # a repository path, from outside the checkout
        candidate = assets_dir().joinpath(*parts[1:])
        return candidate if os.path.isfile(candidate) and text.endswith(SCENE_SUFFIX) else None
    if len(parts) != 1:
        return None
    name = text[: -len(SCENE_SUFFIX)] if text.endswith(SCENE_SUFFIX) else text
    candidate = scene_dir() / f"{name}{SCENE_SUFFIX}"
    return candidate if name and os.path.isfile(candidate) else None


def resolve_scene(target: str | PurePath) -> Path:
    """The scene file ``target`` means: the file itself where it exists, else the bundled scene it names."""
    path = Path(target)
    if os.path.isfile(path):  # Path.is_file raises for a name over 255 bytes; input_file says what it is
        return path
    return bundled_scene(target) or path


def unknown_target(name: str, stages: list[str]) -> str:
    """What to say about a target that is neither a stage nor a scene: the closest name, the stages and the
    bundled scenes (a typo of 'final' listed only the stages, as if scenes were not targets)."""
    import difflib

    scenes = bundled_scene_names()
    close = difflib.get_close_matches(str(name), [*stages, *scenes], n=1)
    guess = f" (did you mean {close[0]!r}?)" if close else ""
    return (f"valid stages are {', '.join(stages)}; bundled scenes are {', '.join(scenes)}; "
            f"or give a scene file (.toml){guess}")
