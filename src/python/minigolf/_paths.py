"""Where the shipped data (fields, models, plants) is found. An installed package (`pip install .`)
carries it in minigolf/data; the build tree's package (PYTHONPATH=build/python) has none there and
uses the source tree recorded at build time (core/io data_dir). MINIGOLF_DATA_DIR, when set, wins."""
import os
import pathlib

PACKAGE_DATA = pathlib.Path(__file__).resolve().parent / "data"
if not os.environ.get("MINIGOLF_DATA_DIR") and (PACKAGE_DATA / "fields").is_dir():
    os.environ["MINIGOLF_DATA_DIR"] = str(PACKAGE_DATA)
