"""nubot_common.kernels, the compiled kernels' loader, on nubot_control's kernels: a package's own build, the
sanitizers' folder first, and a clear error."""

import importlib.machinery
import os
import shutil
import subprocess
import sys

import pytest

from nubot_common.kernels import PATH_VARIABLE, load_kernels


def test_a_package_without_built_kernels_says_how_to_build_them():
    with pytest.raises(ImportError, match=r"nubot_common's compiled kernels \(nubot_common._kernels\) are not built: "
                                          r"run `make setup`"):
        load_kernels("nubot_common")


def test_kernels_in_a_folder_of_the_path_variable_come_first(tmp_path):
    built = load_kernels("nubot_control")
    suffix = next(s for s in importlib.machinery.EXTENSION_SUFFIXES if built.__file__.endswith(s))
    (tmp_path / "nubot_control").mkdir()
    copy = tmp_path / "nubot_control" / f"_kernels{suffix}"
    shutil.copy(built.__file__, copy)
    script = ("import sys; from nubot_common.kernels import load_kernels; from nubot_control.mpc import LaguerreMpc; "
              "print(load_kernels('nubot_control').__file__); "
              "print(sys.modules[LaguerreMpc.__base__.__module__].__file__)")
    env = {**os.environ, PATH_VARIABLE: f"{tmp_path / 'elsewhere'}{os.pathsep}{tmp_path}"}
    out = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, check=True).stdout
    assert out.split() == [str(copy), str(copy)]
