"""The scenes shipped with towcable: one TOML file ``<name>.toml`` per scene (data), and
the reading of a scene's TOML document with the scene it is ``based_on``.

The code that validates a scene is :mod:`towcable_fmu.scene`; this module only finds and
reads the files, so that packages below the scene package (the ShipMotion FMU, the FMU
build's warm-up) can list and read them as the scene loader does.

**Variants.** A scene whose top-level key ``based_on`` names another scene (a built-in
name, or a path to a TOML file, relative to the folder of the file that names it) is that
scene with its own keys laid over: tables merge key by key, at any depth; any other value
(a number, a string, an array, an array of tables such as ``[[cable.segments]]``) replaces
the base's. A base may itself be based on another scene. Relative file paths in the merged
scene resolve against the folder of the scene that was loaded, as if the base's keys were
written there.
"""

from __future__ import annotations

import difflib
import tomllib
from importlib import resources
from pathlib import Path
from typing import Any

from ..common.errors import SceneError

#: The key that names the scene a scene is based on, and its description in the scene schemas.
BASED_ON = "based_on"
BASED_ON_DOC = ("a scene this one is a variant of (built-in name, or path to a TOML file relative to this file's "
                "folder): its keys with this file's laid over, tables merged key by key, other values (arrays "
                "too) replaced")


def builtin_scene_names() -> list[str]:
    """Names of the scenes shipped with the package, sorted."""
    return sorted(p.name[:-5] for p in resources.files(__name__).iterdir() if p.name.endswith(".toml"))


def builtin_scene_text(name: str) -> str:
    """The TOML text of the built-in scene ``name`` (one of :func:`builtin_scene_names`)."""
    return (resources.files(__name__) / f"{name}.toml").read_text(encoding="utf-8")


def scene_document(name_or_path: str | Path, key: str = "scene",
                   relative_to: Path | None = None) -> tuple[dict[str, Any], Path | None]:
    """A scene's TOML document with the scenes it is based on merged in (module docstring).

    Parameters
    ----------
    name_or_path
        A built-in scene name or a path to a TOML file.
    key
        The name the value came under, for error messages (``scene``, ``motion.config``).
    relative_to
        Folder a relative path is taken from (None: the working directory).

    Returns
    -------
    dict, Path or None
        The merged document (``based_on`` kept, the name of the first base) and the folder
        of the file loaded (None for a built-in scene).

    Raises
    ------
    SceneError
        A scene that does not exist, invalid TOML, a ``based_on`` that is not a string,
        names no scene or closes a loop.
    """
    doc, folder, identity = _read(name_or_path, key, relative_to)
    return _with_bases(doc, folder, [identity]), folder


def _read(name_or_path: str | Path, key: str,
          relative_to: Path | None) -> tuple[dict[str, Any], Path | None, str]:
    """The TOML document of one scene file, its folder (None: built-in) and what names the
    file (its resolved path, or the built-in name), for finding loops of ``based_on``."""
    path = Path(name_or_path).expanduser()
    names = builtin_scene_names()
    if path.suffix == ".toml" or path.exists():
        path = ((relative_to or Path.cwd()) / path).resolve()
        if not path.is_file():
            raise SceneError(key, str(name_or_path), "an existing TOML file or a built-in scene name ("
                             + ", ".join(names) + ")")
        text, folder, identity = path.read_text(encoding="utf-8"), path.parent, str(path)
    elif str(name_or_path) in names:
        text, folder, identity = builtin_scene_text(str(name_or_path)), None, str(name_or_path)
    else:
        close = difflib.get_close_matches(str(name_or_path), names, n=1)
        hint = f" (did you mean '{close[0]}'?)" if close else ""
        raise SceneError(key, str(name_or_path), "a built-in scene name (" + ", ".join(names) + ")" + hint
                         + " or a path to a .toml file")
    try:
        return tomllib.loads(text), folder, identity
    except tomllib.TOMLDecodeError as exc:
        raise SceneError(key, str(name_or_path), f"valid TOML ({exc})") from None


def _with_bases(doc: dict[str, Any], folder: Path | None, chain: list[str]) -> dict[str, Any]:
    """``doc`` laid over the scene it is based on (recursively); ``chain``: the scenes read so far."""
    base = doc.get(BASED_ON)
    if base is None:
        return doc
    if not isinstance(base, str) or not base:
        raise SceneError(BASED_ON, base, "the name of a built-in scene or a path to a TOML file (a string)")
    under, under_folder, identity = _read(base, BASED_ON, folder)
    if identity in chain:
        raise SceneError(BASED_ON, base, "a scene that is not based on itself (the loop: "
                         + " -> ".join(chain + [identity]) + ")")
    merged = _merge(_with_bases(under, under_folder, chain + [identity]), doc)
    merged[BASED_ON] = base
    return merged


def _merge(base: dict[str, Any], over: dict[str, Any]) -> dict[str, Any]:
    """``over`` laid over ``base``: tables merged key by key, other values replaced (new dict)."""
    out = dict(base)
    for name, value in over.items():
        out[name] = (_merge(out[name], value) if isinstance(value, dict) and isinstance(out.get(name), dict)
                     else value)
    return out
