"""Shared set-up of the Python tests: the CLI binary and the minigolf package of this build
(ctest sets MINIGOLF_BINARY, PYTHONPATH and MINIGOLF_MPIEXEC; see CMakeLists.txt)."""
import os
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
BINARY = os.environ.get("MINIGOLF_BINARY", str(ROOT / "build" / "src" / "cli" / "minigolf"))
if "PYTHONPATH" not in os.environ:
    sys.path.insert(0, str(ROOT / "build" / "python"))
