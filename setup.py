"""`pip install .` for the minigolf Python package (docs/python.md, "Install with pip").

The extension `minigolf._minigolf` is built by the project's own CMake build (not by setuptools'
compiler): configured in build/pip/cmake with the tests and benchmarks off, and only its target
built. Everything setuptools writes (build_lib, bdist dirs, egg-info) also goes under build/pip;
./build, the developers' CMake build, is not touched. The package is src/python/minigolf (all its
modules) plus the repository's data/ as minigolf/data (src/python/minigolf/_paths.py uses it).

MINIGOLF_EXTENSION=/path/to/_minigolf.<abi>.so (a `_minigolf` target the CMake build already made,
for this interpreter) is packaged as it is instead, with no second build: what the wheel test
(tests/python/test_wheel.py under ctest) does with the build it runs in.

Offline (Debian 12: python3-setuptools, python3-wheel, no PyPI), in a virtual environment:
    /usr/bin/python3 -m venv --system-site-packages .venv
    .venv/bin/python -m pip install --no-build-isolation .
"""
import os
import pathlib
import re
import shutil
import subprocess
import sys
import sysconfig

from setuptools import Extension, find_packages, setup
from setuptools.command.build_ext import build_ext
from setuptools.command.build_py import build_py

ROOT = pathlib.Path(__file__).resolve().parent
PIP_BUILD = ROOT / "build" / "pip"  # setuptools' build_base and egg_info base, and the CMake build
CMAKE_BUILD = PIP_BUILD / "cmake"
DATA = ROOT / "data"


def cmake_project_version():
    """VERSION of `project(minigolf VERSION x.y.z ...)` in the top-level CMakeLists.txt."""
    text = (ROOT / "CMakeLists.txt").read_text(encoding="utf-8")
    m = re.search(r"^\s*project\s*\(\s*minigolf\s+VERSION\s+([0-9]+(?:\.[0-9]+)*)", text,
                  re.MULTILINE | re.IGNORECASE)
    if not m:
        raise RuntimeError(f"no 'project(minigolf VERSION ...)' in {ROOT / 'CMakeLists.txt'}")
    return m.group(1)


def jobs():
    try:
        return len(os.sched_getaffinity(0))  # what nproc prints
    except (AttributeError, OSError):
        return os.cpu_count() or 1


class CMakeBuildExt(build_ext):
    """Builds `_minigolf` with CMake and copies it to where setuptools expects the extension."""

    def build_extension(self, ext):
        if ext.name != "minigolf._minigolf":
            return super().build_extension(ext)
        suffix = sysconfig.get_config_var("EXT_SUFFIX") or ".so"
        dest = pathlib.Path(self.get_ext_fullpath(ext.name))
        dest.parent.mkdir(parents=True, exist_ok=True)
        prebuilt = os.environ.get("MINIGOLF_EXTENSION")
        if prebuilt:  # one build of the extension, not two
            p = pathlib.Path(prebuilt)
            if not p.is_file() or p.name != "_minigolf" + suffix:
                raise RuntimeError(f"MINIGOLF_EXTENSION: expected an existing _minigolf{suffix}, got '{prebuilt}'")
            print(f"minigolf setup.py: packaging the prebuilt {p} (MINIGOLF_EXTENSION)", flush=True)
            self.copy_file(str(p), str(dest))
            return
        configure = ["cmake", "-S", str(ROOT), "-B", str(CMAKE_BUILD), "-DCMAKE_BUILD_TYPE=Release",
                     "-DMINIGOLF_BUILD_TESTS=OFF", "-DMINIGOLF_BUILD_BENCHMARKS=OFF",
                     f"-DPython3_EXECUTABLE={sys.executable}"]
        env = dict(os.environ)
        if shutil.which("ccache"):
            configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
            # as scripts/sanitize.sh: a clone elsewhere hits the same cache entries
            env.setdefault("CCACHE_BASEDIR", str(ROOT))
            env.setdefault("CCACHE_NOHASHDIR", "1")
        else:
            configure.append("-DCMAKE_CXX_COMPILER_LAUNCHER=")  # a cached ccache that is gone
        build = ["cmake", "--build", str(CMAKE_BUILD), "--target", "_minigolf", "-j", str(jobs())]
        CMAKE_BUILD.mkdir(parents=True, exist_ok=True)
        for cmd in (configure, build):
            print("minigolf setup.py:", " ".join(cmd), flush=True)
            subprocess.check_call(cmd, cwd=ROOT, env=env)

        built = sorted((CMAKE_BUILD / "python" / "minigolf").glob("_minigolf*.so"))
        matching = [p for p in built if p.name == "_minigolf" + suffix]
        if not matching:
            raise RuntimeError(f"CMake built no _minigolf{suffix} in {CMAKE_BUILD / 'python' / 'minigolf'}"
                               f" (found: {[p.name for p in built]})")
        self.copy_file(str(matching[0]), str(dest))


class BuildPyWithData(build_py):
    """The package's modules as usual, plus the repository's data/ copied to minigolf/data."""

    def data_files_to_copy(self):
        for src in sorted(DATA.rglob("*")):
            if src.is_file() and "__pycache__" not in src.parts:
                yield src, pathlib.Path(self.build_lib, "minigolf", "data", src.relative_to(DATA))

    def run(self):
        super().run()
        if getattr(self, "editable_mode", False):
            return  # an editable install finds data/ through the source tree (core/io data_dir)
        target = pathlib.Path(self.build_lib, "minigolf", "data")
        if target.is_dir():
            shutil.rmtree(target)  # mirror data/: no files left over from an earlier build
        for src, dst in self.data_files_to_copy():
            dst.parent.mkdir(parents=True, exist_ok=True)
            self.copy_file(str(src), str(dst), preserve_mode=False)

    def get_outputs(self, include_bytecode=True):
        outputs = super().get_outputs(include_bytecode)
        if not getattr(self, "editable_mode", False):
            outputs += [str(dst) for _, dst in self.data_files_to_copy()]
        return outputs


PIP_BUILD.mkdir(parents=True, exist_ok=True)  # egg_info requires its base to exist

setup(
    version=cmake_project_version(),
    package_dir={"": "src/python"},
    packages=find_packages(where="src/python", include=["minigolf", "minigolf.*"]),
    ext_modules=[Extension("minigolf._minigolf", sources=[])],
    cmdclass={"build_ext": CMakeBuildExt, "build_py": BuildPyWithData},
    options={"build": {"build_base": str(PIP_BUILD)}, "egg_info": {"egg_base": str(PIP_BUILD)}},
    zip_safe=False,
)
