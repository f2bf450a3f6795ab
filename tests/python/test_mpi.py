"""Scale-out: `mpirun -np N minigolf sweep|collect|evaluate|curves ...` gives the same bits as one
process (system/distributed.hpp). Skipped where minigolf was built without MPI."""
import os
import subprocess

import pytest

from conftest import BINARY, ROOT

MPIEXEC = os.environ.get("MINIGOLF_MPIEXEC", "")
pytestmark = pytest.mark.skipif(not MPIEXEC, reason="minigolf was built without MPI (CMake found no OpenMPI; "
                                                    "apt-get install libopenmpi-dev openmpi-bin)")
ENV = dict(os.environ, OMPI_MCA_btl_vader_single_copy_mechanism="none", OMPI_MCA_rmaps_base_oversubscribe="1")


def run(ranks, *args, check=True):
    cmd = [BINARY, *args]
    if ranks:
        cmd = [MPIEXEC, "--oversubscribe", "--allow-run-as-root", "-np", str(ranks), *cmd]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=900, env=ENV)
    if check:
        assert r.returncode == 0, f"{' '.join(cmd)}: {r.stderr}"
    return r


def same_run(tmp_path, make_args, ranks=(2,)):
    """Runs the command in one process and under mpirun; returns the outputs (file bytes, stdout)."""
    results = {}
    for n in (0, *ranks):
        out = tmp_path / f"np{n}.csv"
        r = run(n, *make_args(str(out)))
        results[n] = (out.read_bytes(), r.stdout)
    for n in ranks:
        assert results[n][0] == results[0][0], f"-np {n}: the file differs from one process's"
        assert results[n][1].replace(f"np{n}.csv", "X") == results[0][1].replace("np0.csv", "X"), \
            f"-np {n}: the output differs"
    return results[0]


def test_sweep_ball_only_same_bits_for_2_and_3_ranks(tmp_path):
    data, stdout = same_run(tmp_path, lambda out: ["sweep", "--field", "flat", "--angles", "-0.03:0.03:7",
                                                   "--speeds", "0.8:2.0:5", "--ball-only", "--threads", "1",
                                                   "-o", out], ranks=(2, 3))
    assert data.count(b"\n") == 36 and "cells sink" in stdout and stdout.count("\n") == 1


def test_sweep_arm_same_bits(tmp_path):
    same_run(tmp_path, lambda out: ["sweep", "--field", "flat", "--angles", "-0.02:0.04:3", "--speeds",
                                    "1.0:1.6:2", "--threads", "1", "-o", out])


def test_evaluate_same_bits(tmp_path):
    model = tmp_path / "gpr.json"
    run(0, "train", str(ROOT / "data" / "datasets" / "flat.csv"), "--restarts", "2", "-o", str(model))
    _, stdout = same_run(tmp_path, lambda out: ["evaluate", "--field", "flat", "--model", str(model),
                                                "--situations", "5", "--no-oracle", "--threads", "1",
                                                "--json", "-o", out])
    assert '"success_ratio"' in stdout


def test_collect_same_bits(tmp_path):
    same_run(tmp_path, lambda out: ["collect", "--field", "flat", "--situations", "list:1.9,0.05;2.0,-0.05;2.1,0.0",
                                    "--max-full-putts", "12", "--threads", "1", "-o", out])


def test_learning_curves_same_bits_for_2_and_3_ranks(tmp_path):
    data, stdout = same_run(tmp_path, lambda out: ["curves", "--field", "flat", "--learner", "self-teach",
                                                   "--seeds", "3", "--checkpoints", "4,8", "--situations", "6",
                                                   "--threads", "1", "-o", out], ranks=(2, 3))
    assert data.count(b"\n") == 1 + 3 * 2 and stdout.count("median") == 2


def test_an_error_is_reported_once_with_the_exit_code(tmp_path):
    r = run(2, "sweep", "--field", "no-such-field", "--angles", "0:0:1", "--speeds", "1:1:1", "--ball-only",
            "-o", str(tmp_path / "x.csv"), check=False)
    one = run(0, "sweep", "--field", "no-such-field", "--angles", "0:0:1", "--speeds", "1:1:1", "--ball-only",
              "-o", str(tmp_path / "x.csv"), check=False)
    assert one.returncode == 2 and r.returncode == 2
    assert r.stderr.count(one.stderr.strip()) == 1  # rank 0's line (mpirun adds its abort notice)


def test_launch_study_same_bits(tmp_path):
    outs = {}
    for n in (0, 2):
        out = tmp_path / f"np{n}"
        r = run(n, "study", "launch-error", "--field", "flat", "--angles-deg", "-5,5", "--hits", "3", "--threads", "1",
                "--out", str(out), "--json")
        outs[n] = ((out / "launch_error.csv").read_bytes(), r.stdout)
    assert outs[2] == outs[0]
