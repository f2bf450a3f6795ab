"""The main job's figure: the demo putts over the four shipped fields (OUT/fields.png).

Reads OUT/heights_<field>.csv, OUT/field_<field>.json and OUT/putt_*_<field>.csv/.json."""
import glob
import json
import os

import matplotlib.pyplot as plt

from .common import PlotError, save
from .field import draw_field, read_heights, read_trajectory

FIELDS = ["flat", "multiple-hills", "regular-hill", "arctan"]


def _unique_keys(pairs):
    """json's object_pairs_hook: a key given twice is an error (json keeps the last one)."""
    out = {}
    for key, value in pairs:
        if key in out:
            raise ValueError(f"duplicate key '{key[:80]}'")
        out[key] = value
    return out


def read_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f, object_pairs_hook=_unique_keys)
    except FileNotFoundError:
        raise PlotError(f"{path}: no such file") from None
    except (OSError, ValueError) as e:
        raise PlotError(f"{path}: cannot read JSON: {e}") from None


def _key(data, key, path):
    if key not in data:
        raise PlotError(f"{path}: missing key '{key}'")
    return data[key]


def plot_demo(out, fields=FIELDS):
    fig, axes = plt.subplots(len(fields), 1, figsize=(9, 3.2 * len(fields)), squeeze=False)
    for ax, name in zip(axes[:, 0], fields):
        heights = read_heights(os.path.join(out, f"heights_{name}.csv"))
        info_path = os.path.join(out, f"field_{name}.json")
        info = read_json(info_path)
        trajectories = []
        for path in sorted(glob.glob(os.path.join(out, f"putt_*_{name}.csv"))):
            res_path = path[:-len(".csv")] + ".json"
            res = read_json(res_path)
            angle, speed = _key(res, "angle", res_path), _key(res, "speed", res_path)
            sunk = "sunk" if _key(res, "sunk", res_path) else "missed"
            trajectories.append((*read_trajectory(path),
                                 f"angle {angle:.2f} rad, {speed:.1f} m/s: {sunk}"))
        draw_field(fig, ax, heights, trajectories, [tuple(_key(info, "hole", info_path))],
                   tuple(_key(info, "tee", info_path)), _key(info, "hole_diameter", info_path))
        ax.set_title(f"{name}: {info.get('description', '')}", fontsize=9)
    fig.tight_layout()
    save(fig, os.path.join(out, "fields.png"), dpi=110)
