"""`pip wheel .` / `pip install` of the minigolf package (pyproject.toml, setup.py): builds the wheel
offline with Debian's /usr/bin/python3 (setuptools, wheel, no build isolation), installs it into a
fresh virtual environment (with the system site packages, for Debian's numpy) and uses it from
outside the repository, with PYTHONPATH and MINIGOLF_DATA_DIR unset: the package, its shipped data,
a putt and examples/train_policy.py all come from the virtual environment.

The wheel's extension is the one the CMake build made when MINIGOLF_EXTENSION names it (ctest sets it
and MINIGOLF_SOURCE_DIR: tests/python/CMakeLists.txt, test python_wheel; setup.py packages it as it
is), else pip builds it with CMake in <source>/build/pip/cmake (ccache makes a rebuild quick)."""
import json
import os
import pathlib
import re
import subprocess
import sys
import zipfile

import pytest

ROOT = pathlib.Path(os.environ.get("MINIGOLF_SOURCE_DIR") or pathlib.Path(__file__).resolve().parents[2]).resolve()
PYTHON = "/usr/bin/python3"  # Debian's: its pip, venv, setuptools, wheel and numpy
FIELDS = {"flat", "arctan", "regular-hill", "multiple-hills"}


def missing_tools():
    """Why the test cannot run here (None when /usr/bin/python3 has pip and venv)."""
    if not os.access(PYTHON, os.X_OK):
        return f"{PYTHON} is not available"
    if subprocess.run([PYTHON, "-m", "pip", "--version"], capture_output=True).returncode != 0:
        return f"{PYTHON} -m pip is not available (Debian: apt install python3-pip)"
    if subprocess.run([PYTHON, "-c", "import venv, ensurepip"], capture_output=True).returncode != 0:
        return f"{PYTHON} -m venv is not available (Debian: apt install python3-venv)"
    return None


MISSING = missing_tools()
pytestmark = pytest.mark.skipif(MISSING is not None, reason=str(MISSING))


def clean_env():
    """The environment of every child: no PYTHONPATH (nor a data folder) pointing at the repository."""
    env = dict(os.environ)
    for var in ("PYTHONPATH", "PYTHONHOME", "PYTHONSTARTUP", "MINIGOLF_DATA_DIR", "VIRTUAL_ENV"):
        env.pop(var, None)
    env.update(PYTHONNOUSERSITE="1", PIP_DISABLE_PIP_VERSION_CHECK="1", PIP_NO_INPUT="1")
    return env


def run(cmd, cwd, timeout=600):
    r = subprocess.run([str(c) for c in cmd], cwd=cwd, env=clean_env(), capture_output=True, text=True,
                       timeout=timeout)
    assert r.returncode == 0, (f"{' '.join(map(str, cmd))} exited {r.returncode}\n"
                               f"--- stdout\n{r.stdout[-6000:]}\n--- stderr\n{r.stderr[-6000:]}")
    return r


def inside(path, folder):
    return pathlib.Path(path).resolve().is_relative_to(pathlib.Path(folder).resolve())


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(wheel, venv, its python, a working folder outside the repository)."""
    base = tmp_path_factory.mktemp("wheel")
    dist, venv, work = base / "dist", base / "venv", base / "work"
    work.mkdir()
    run([PYTHON, "-m", "pip", "wheel", "--no-build-isolation", "--no-deps", "-w", dist, ROOT], cwd=work,
        timeout=1150)
    wheels = sorted(dist.glob("minigolf-*.whl"))
    assert len(wheels) == 1, wheels
    run([PYTHON, "-m", "venv", "--system-site-packages", venv], cwd=work)
    python = venv / "bin" / "python"
    run([python, "-m", "pip", "install", "--no-deps", "--no-index", wheels[0]], cwd=work)
    return wheels[0], venv, python, work


def child(installed, code):
    """Runs `code` with the venv's python outside the repository; returns what it printed as JSON."""
    _, _, python, work = installed
    return json.loads(run([python, "-c", code], cwd=work).stdout.strip().splitlines()[-1])


def test_wheel_contents(installed):
    wheel = installed[0]
    names = set(zipfile.ZipFile(wheel).namelist())
    modules = {f"minigolf/{p.name}" for p in (ROOT / "src" / "python" / "minigolf").glob("*.py")}
    assert modules <= names, modules - names
    data = {f"minigolf/data/{p.relative_to(ROOT / 'data').as_posix()}"
            for p in (ROOT / "data").rglob("*") if p.is_file()}
    assert data and data == {n for n in names if n.startswith("minigolf/data/")}
    assert any(re.fullmatch(r"minigolf/_minigolf\..*\.so", n) for n in names), sorted(names)
    prebuilt = os.environ.get("MINIGOLF_EXTENSION")
    if prebuilt:  # the build's extension, packaged as it is (no second build)
        so = [n for n in names if re.fullmatch(r"minigolf/_minigolf\..*\.so", n)][0]
        assert zipfile.ZipFile(wheel).read(so) == pathlib.Path(prebuilt).read_bytes()


def test_import_comes_from_the_venv(installed):
    _, venv, _, work = installed
    r = child(installed, "import json, minigolf, minigolf._minigolf as m, minigolf.env as e; "
                         "print(json.dumps([minigolf.__file__, m.__file__, e.__file__]))")
    for f in r:
        assert inside(f, venv), f"{f} is not in {venv}"
        assert not inside(f, ROOT), f"{f} is in the repository"


def test_shipped_fields_from_the_package_data(installed):
    _, venv, _, _ = installed
    r = child(installed, "import json, os; before = os.environ.get('MINIGOLF_DATA_DIR'); import minigolf; "
                         "print(json.dumps({'before': before, 'data': os.environ.get('MINIGOLF_DATA_DIR'), "
                         "'package': minigolf.__file__, 'shipped': list(minigolf.Field.shipped()), "
                         "'source': minigolf.Field.load('flat').source}))")
    assert r["before"] is None
    package_data = pathlib.Path(r["package"]).resolve().parent / "data"
    assert inside(package_data, venv)
    assert pathlib.Path(r["data"]).resolve() == package_data  # set by minigolf/_paths.py
    assert inside(r["source"], package_data), r["source"]      # what the library read
    assert FIELDS <= set(r["shipped"]), r["shipped"]
    assert r["shipped"] == sorted(p.stem for p in (ROOT / "data" / "fields").glob("*.yaml"))


def test_ball_only_putt(installed):
    r = child(installed, "import json, math, minigolf; "
                         "p = minigolf.System(field='flat').putt(0.0, 1.3, ball_only=True); "
                         "print(json.dumps({'sunk': bool(p.sunk), 'closest': float(p.closest_approach), "
                         "'shape': list(p.trajectory.shape)}))")
    assert r["shape"][0] > 1 and r["shape"][1] == 7, r
    assert r["closest"] >= 0.0, r


def test_train_policy_example_uses_the_installed_package(installed):
    _, venv, python, work = installed
    script = ROOT / "examples" / "train_policy.py"
    # -v: the interpreter reports where each module was loaded from (on stderr)
    r = run([python, "-v", script, "--iterations", "1", "--episodes", "5", "--test", "5"], cwd=work)
    assert "iteration 1:" in r.stdout and "success ratio" in r.stdout, r.stdout
    loaded = re.findall(r"^# extension module 'minigolf\._minigolf' loaded from '(.+)'$", r.stderr, re.MULTILINE)
    assert loaded, "train_policy.py did not load minigolf._minigolf"
    sources = [p for p in re.findall(r"^# code object from '(.+)'$", r.stderr, re.MULTILINE)
               if re.search(r"/minigolf/(__pycache__/)?__init__\.", p)]
    assert sources, "train_policy.py did not import the minigolf package"
    for f in loaded + sources:
        assert inside(f, venv), f"train_policy.py used {f}, not the package installed in {venv}"
