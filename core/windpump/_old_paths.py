"""The modules' paths before the core's sub-packages (issue 38), kept working.

``import windpump.dynamics`` gives :mod:`windpump.run.dynamics` itself, the same module object,
so a name read or patched through the old path is the new module's. ``windpump.windmill`` was one
module and is two: the windmill's curve (:mod:`windpump.model.windmill`) and where it meets the
load line (:mod:`windpump.averaging.operating`); its old path offers the names of both.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
import types

# old path under windpump -> the module(s) now holding its names
MOVED: dict[str, str | tuple[str, ...]] = {
    **{name: f"windpump.model.{name}" for name in ("design", "groups", "kinematics", "loads")},
    **{name: f"windpump.model.{name}" for name in ("reciprocating", "wind")},
    "windmill": ("windpump.model.windmill", "windpump.averaging.operating"),
    "_kernels.equations": "windpump.model.equations",
    **{name: f"windpump.averaging.{name}" for name in ("revolution", "theory", "averaged")},
    **{name: f"windpump.run.{name}" for name in ("dynamics", "energy", "exploration", "playback")},
    **{name: f"windpump.sites.{name}" for name in ("site", "hours", "fullyear", "yearly")},
    "weather": "windpump.sites.weather",
    **{name: f"windpump.study.{name}" for name in ("studies", "maps")},
    **{name: f"windpump.readers.{name}" for name in ("files", "labdata")},
    **{name: f"windpump.command.{name}" for name in ("cli", "cliargs", "sitecli")},
}


class Joined(types.ModuleType):
    """An old module whose names now live in several: each name read from the first that has it."""

    def __init__(self, name: str, parts: list[types.ModuleType]):
        super().__init__(name, f"{name}: its names now in {', '.join(p.__name__ for p in parts)}")
        self._parts = parts

    def __getattr__(self, attribute: str):
        if attribute.startswith("__"):  # its own __file__ etc., not a part's
            raise AttributeError(attribute)
        for part in self._parts:
            if hasattr(part, attribute):
                return getattr(part, attribute)
        raise AttributeError(f"module {self.__name__!r} has no attribute {attribute!r}")

    def __dir__(self):
        return sorted({name for part in self._parts for name in dir(part)})


class OldPaths(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds ``windpump.<old path>`` and loads it as the module now holding it."""

    def find_spec(self, fullname, path=None, target=None):
        if fullname.removeprefix("windpump.") in MOVED and fullname.startswith("windpump."):
            return importlib.util.spec_from_loader(fullname, self)
        return None

    def __init__(self) -> None:
        self.specs: dict[str, object] = {}

    def create_module(self, spec):
        module = moved(spec.name.removeprefix("windpump."))
        self.specs[spec.name] = module.__spec__  # Python sets the old path's over it
        return module

    def exec_module(self, module):
        # the module is the new one, already run: its own spec back
        own = self.specs.pop(module.__spec__.name)
        if own is not None:  # a Joined module keeps the old path's
            module.__spec__ = own


def moved(old: str) -> types.ModuleType:
    """The module an old path names now (imported)."""
    new = MOVED[old]
    if isinstance(new, str):
        return importlib.import_module(new)
    return Joined(f"windpump.{old}", [importlib.import_module(name) for name in new])


def install() -> None:
    """Put the finder last on Python's path (once): a module that exists is always found first."""
    if not any(isinstance(finder, OldPaths) for finder in sys.meta_path):
        sys.meta_path.append(OldPaths())
