"""The packages' compiled kernels: each package's numeric work under its Python API, the extension module
``<package>._kernels`` (C++17 with Eigen, bound by pybind11), which ``catkin_make`` builds into the package's folder
(``nubot_add_kernels`` in ``nubot_common/cmake/nubot_kernels.cmake``).

``load_kernels(package)`` imports it, or raises ImportError saying how to build it. Folders named in the
environment variable ``NUBOT_KERNELS_PATH`` (``os.pathsep``-separated, each holding ``<package>/_kernels*.so``) come
first: ``make sanitize`` runs the tests on kernels built there with the sanitizers.
"""

from __future__ import annotations

import importlib
import importlib.machinery
import importlib.util
import os
import sys
from pathlib import Path
from types import ModuleType

PATH_VARIABLE = "NUBOT_KERNELS_PATH"


def load_kernels(package: str) -> ModuleType:
    """``<package>._kernels``, from ``NUBOT_KERNELS_PATH`` if a folder there has it, else from the package."""
    name = f"{package}._kernels"
    if name in sys.modules:
        return sys.modules[name]
    for folder in filter(None, os.environ.get(PATH_VARIABLE, "").split(os.pathsep)):
        for suffix in importlib.machinery.EXTENSION_SUFFIXES:
            path = Path(folder) / package / f"_kernels{suffix}"
            if path.is_file():
                spec = importlib.util.spec_from_file_location(name, path)
                assert spec is not None and spec.loader is not None
                module = importlib.util.module_from_spec(spec)
                sys.modules[name] = module
                spec.loader.exec_module(module)
                return module
    try:
        return importlib.import_module(name)
    except ImportError as exc:
        raise ImportError(f"{package}'s compiled kernels ({name}) are not built: run `make setup` (or catkin_make "
                          f"at the workspace's root) and source devel/setup.bash ({exc})") from exc
