"""minigolf.play: a round from Python, the same dict and bits as `minigolf play --json`."""
import json
import os
import subprocess

import pytest

import minigolf

COURSE = """format_version: 1
name: tiny
max_strokes: 4
holes:
  - {field: flat, tee: [0.2, 0.1], hole: [1.4, -0.1], par: 2}
"""


@pytest.fixture()
def course(tmp_path):
    path = tmp_path / "tiny.yaml"
    path.write_text(COURSE)
    return str(path)


def test_shipped_courses_are_listed():
    names = minigolf.courses()
    assert {"thesis", "open-lane", "obstacles"} <= set(names)


def test_a_round_has_the_documented_keys_and_finishes(course):
    r = minigolf.play(course, player="oracle", seed=2)
    assert r["course"] == "tiny"
    assert set(r) >= {"course", "holes", "total_strokes", "total_par", "learning_putts"}
    hole = r["holes"][0]
    assert hole["sunk"] and 1 <= hole["strokes"] <= 4
    assert r["total_strokes"] == sum(h["strokes"] for h in r["holes"])
    first = hole["putts"][0]
    assert set(first) >= {"ball", "angle", "speed", "rest", "sunk"}
    assert first["ball"] == pytest.approx([0.2, 0.1])


def test_python_and_the_cli_give_the_same_round(course):
    py = minigolf.play(course, player="greedy", seed=5, budget=3)
    out = subprocess.run(
        [os.environ["MINIGOLF_BINARY"], "play", "--course", course, "--player", "greedy",
         "--seed", "5", "--budget", "3", "--json"],
        check=True, capture_output=True, text=True).stdout
    assert json.loads(out) == py
    assert py["learning_putts"] == 3


def test_bad_arguments_are_value_errors(course):
    with pytest.raises(ValueError, match="course"):
        minigolf.play("no-such-course")
    with pytest.raises(ValueError, match="player"):
        minigolf.play(course, player="tiger")
    with pytest.raises(ValueError, match="budget"):
        minigolf.play(course, budget=0)
    # The CLI's --threads is 0..256; Python took -1 and 100000.
    for threads in (-1, 257, 100000):
        with pytest.raises(ValueError, match="threads: expected 0..256"):
            minigolf.play(course, player="greedy", threads=threads)


def test_a_learned_model_plays_where_it_sinks(tmp_path):
    # The shipped flat data set's line (xi = (2, -0.2..0.4)), seen from a moved tee.
    course = tmp_path / "model.yaml"
    course.write_text(COURSE.replace("hole: [1.4, -0.1]", "hole: [2.2, 0.2]"))
    course = str(course)
    data = os.path.join(os.path.dirname(__file__), "..", "..", "data", "datasets", "flat.csv")
    model = tmp_path / "flat.json"
    subprocess.run([os.environ["MINIGOLF_BINARY"], "train", "--method", "gpr", data, "-o",
                    str(model)], check=True, capture_output=True)
    r = minigolf.play(course, seed=2, budget=4, models={"flat": str(model)})
    assert r["holes"][0]["putts"][0]["model"] is True
    with pytest.raises(ValueError, match="models"):
        minigolf.play(course, player="oracle", models={"flat": str(model)})
    with pytest.raises(Exception, match="no-such-field"):
        minigolf.play(course, models={"no-such-field": str(model)})
