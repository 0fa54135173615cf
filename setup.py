"""Builds the roadcross extension module with the project's CMake (see pyproject.toml).

The extension is the CMake target roadcross_python of a runtime-only build (no GDAL, CGAL or
libosmium needed). Installed beside it: roadcross.pyi (read by pyright/Pylance and jedi from the
module's directory) and the PEP 561 stub-only package roadcross-stubs (the same stub, with a
py.typed marker; mypy finds the types of a single-module distribution only there).
"""

import os
import re
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCE_DIR = Path(__file__).resolve().parent


def project_version() -> str:
    text = (SOURCE_DIR / "CMakeLists.txt").read_text()
    match = re.search(r"project\(roadcross VERSION ([0-9.]+)", text)
    if not match:
        raise RuntimeError("CMakeLists.txt: no 'project(roadcross VERSION x.y.z'")
    return match.group(1)


class CMakeExtension(Extension):
    def __init__(self, name: str) -> None:
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    """Configures a runtime-only CMake build for this interpreter and builds roadcross_python."""

    def build_extension(self, ext: Extension) -> None:
        build_dir = Path(self.build_temp).resolve() / "cmake"
        build_dir.mkdir(parents=True, exist_ok=True)
        jobs = os.environ.get("CMAKE_BUILD_PARALLEL_LEVEL", "2")
        configure = [
            "cmake", "-S", str(SOURCE_DIR), "-B", str(build_dir),
            "-DCMAKE_BUILD_TYPE=Release",
            "-DROADCROSS_RUNTIME_ONLY=ON",
            "-DROADCROSS_BUILD_PYTHON=ON",
            "-DROADCROSS_BUILD_ROS=OFF",
            "-DROADCROSS_BUILD_TESTS=OFF",
            "-DROADCROSS_BUILD_BENCHMARKS=OFF",
            f"-DPython_EXECUTABLE={sys.executable}",
        ]
        if shutil.which("ccache"):
            configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
        subprocess.run(configure, check=True)
        subprocess.run(["cmake", "--build", str(build_dir), "--target", "roadcross_python",
                        "-j", jobs], check=True)
        suffix = sysconfig.get_config_var("EXT_SUFFIX")
        built = build_dir / "python" / "module" / f"roadcross{suffix}"
        if not built.is_file():
            raise RuntimeError(f"CMake built no {built}")
        target = Path(self.get_ext_fullpath(ext.name))
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(built, target)
        self.copy_stubs(target.parent)

    @staticmethod
    def copy_stubs(directory: Path) -> None:
        """The stub beside the module and as the stub-only package roadcross-stubs (here, not in
        build_py: a distribution without pure-Python packages never runs build_py)."""
        stub = SOURCE_DIR / "python" / "roadcross.pyi"
        shutil.copy2(stub, directory / "roadcross.pyi")
        stubs_package = directory / "roadcross-stubs"
        stubs_package.mkdir(parents=True, exist_ok=True)
        shutil.copy2(stub, stubs_package / "__init__.pyi")
        (stubs_package / "py.typed").write_text("")


setup(
    version=project_version(),
    ext_modules=[CMakeExtension("roadcross")],
    cmdclass={"build_ext": CMakeBuild},
    packages=[],
    py_modules=[],
    zip_safe=False,
)
