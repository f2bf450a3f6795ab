"""Shared helpers: CSV reading with one-line errors, units, atomic PNG writing."""
import csv
import math
import os
import stat
import tempfile

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

DPI = 120
HOLE_DIAMETER = 0.108  # [m]


class PlotError(Exception):
    """An input problem; the command line prints it as one 'plot: error:' line and exits 2."""


TRUE_WORDS = {"1": True, "true": True, "0": False, "false": False}


class Table:
    """The columns of one CSV file, read as text; typed access names the file and column."""

    def __init__(self, path, header, rows):
        self.path, self.header, self.rows = path, header, rows
        self.index = {name: k for k, name in enumerate(header)}

    def __len__(self):
        return len(self.rows)

    def has(self, column):
        return column in self.index

    def _cells(self, column):
        if column not in self.index:
            raise PlotError(f"{self.path}: missing column '{column}' (header: {','.join(self.header)})")
        k = self.index[column]
        return [(line, row[k]) for line, row in self.rows]

    def text(self, column):
        return [cell for _, cell in self._cells(column)]

    def numbers(self, column, blank_ok=False):
        """Floats (nan and inf accepted as written by the C++ side); a blank cell is nan only
        with blank_ok."""
        out = np.empty(len(self.rows))
        for i, (line, cell) in enumerate(self._cells(column)):
            if cell == "" and blank_ok:
                out[i] = math.nan
                continue
            try:
                out[i] = float(cell)
            except ValueError:
                raise PlotError(f"{self.path}: line {line}, column '{column}': "
                                f"'{cell}' is not a number") from None
        return out

    def booleans(self, column):
        out = np.empty(len(self.rows), dtype=bool)
        for i, (line, cell) in enumerate(self._cells(column)):
            word = cell.lower()
            if word not in TRUE_WORDS:
                raise PlotError(f"{self.path}: line {line}, column '{column}': "
                                f"'{cell}' is not 0/1/true/false")
            out[i] = TRUE_WORDS[word]
        return out


def read_csv(path, required=()):
    """Reads a CSV with a header row; checks that the required columns exist and that every row
    has as many cells as the header. Extra columns are kept and ignored by the callers."""
    try:
        with open(path, newline="", encoding="utf-8") as f:
            lines = list(csv.reader(f))
    except FileNotFoundError:
        raise PlotError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError, csv.Error) as e:
        raise PlotError(f"{path}: cannot read: {e}") from None
    # Blank lines and '#' comment lines are skipped, as the project's C++ CSV reader does.
    numbered = [(n, [c.strip() for c in row]) for n, row in enumerate(lines, 1)
                if any(row) and not row[0].lstrip().startswith("#")]
    if not numbered:
        raise PlotError(f"{path}: empty file (no header row)")
    (_, header), body = numbered[0], numbered[1:]
    for line, row in body:
        if len(row) != len(header):
            raise PlotError(f"{path}: line {line} has {len(row)} cells, the header has {len(header)}")
    if not body:
        raise PlotError(f"{path}: no data rows after the header")
    table = Table(path, header, body)
    for column in required:
        table._cells(column)
    return table


def parse_point(text, option):
    """'X,Y' -> (x, y) for --hole / --tee."""
    try:
        x, y = (float(v) for v in text.split(","))
    except ValueError:
        raise PlotError(f"{option}: '{text}' is not X,Y in metres") from None
    return x, y


# Display scale and axis label per known column (angles in rad in the CSVs, drawn in degrees).
UNITS = {
    "angle": (180.0 / math.pi, "angle [deg]"),
    "launch_angle": (180.0 / math.pi, "launch angle [deg]"),
    "speed": (1.0, "speed [m/s]"),
    "launch_speed": (1.0, "launch speed [m/s]"),
    "xi_x": (1.0, "ξ_x: hole - ball, x [m]"),
    "xi_y": (1.0, "ξ_y: hole - ball, y [m]"),
    "hole_x": (1.0, "hole x [m]"),
    "hole_y": (1.0, "hole y [m]"),
    "x": (1.0, "x [m]"),
    "y": (1.0, "y [m]"),
}


def unit(column):
    """(scale, label) for a column: values * scale are drawn, the label names the unit."""
    return UNITS.get(column, (1.0, column))


def regular_grid(table, xcol, ycol, x, y):
    """Unique sorted x and y of a full grid and, for every row, its (iy, ix) cell. Raises
    PlotError naming the file when the rows are not exactly one per cell."""
    xs, ix = np.unique(np.round(x, 9), return_inverse=True)
    ys, iy = np.unique(np.round(y, 9), return_inverse=True)
    cells = set(zip(iy.tolist(), ix.tolist()))
    if len(cells) != len(x) or len(x) != len(xs) * len(ys):
        raise PlotError(f"{table.path}: columns '{xcol}','{ycol}' are not a full grid "
                        f"({len(xs)} x {len(ys)} = {len(xs) * len(ys)} cells, {len(x)} rows)")
    return xs, ys, iy, ix


def on_grid(values, iy, ix, shape):
    grid = np.full(shape, np.nan)
    grid[iy, ix] = values
    return grid


def edges(centres):
    """Cell edges around sorted centres (for pcolormesh with uneven spacing)."""
    c = np.asarray(centres, dtype=float)
    if len(c) == 1:
        return np.array([c[0] - 0.5, c[0] + 0.5])
    mid = (c[1:] + c[:-1]) / 2
    return np.concatenate([[2 * c[0] - mid[0]], mid, [2 * c[-1] - mid[-1]]])


def save(fig, path, dpi=DPI):
    """Writes the figure as PNG atomically: a temp file in the same directory, then os.replace.

    Like the C++ writers, it never replaces what is not a regular file (a link, FIFO, device or
    folder) and names an unwritable folder in one line."""
    directory = os.path.dirname(os.path.abspath(path))
    try:
        if not os.path.isdir(directory):
            raise PlotError(f"{path}: output directory '{directory}' does not exist")
        try:
            mode = os.lstat(path).st_mode
        except FileNotFoundError:
            mode = None
        if mode is not None and not stat.S_ISREG(mode):
            raise PlotError(f"{path}: exists and is not a regular file; refusing to replace it")
        try:
            fd, tmp = tempfile.mkstemp(dir=directory, prefix=".plot-", suffix=".png")
        except OSError as e:
            raise PlotError(f"{path}: cannot write in '{directory}': {e.strerror}") from None
    except PlotError:
        plt.close(fig)
        raise
    mask = os.umask(0)
    os.umask(mask)
    try:
        os.chmod(tmp, 0o666 & ~mask)  # mkstemp makes 0600; give the PNG the usual permissions
        with os.fdopen(fd, "wb") as f:
            fig.savefig(f, format="png", dpi=dpi)
        os.replace(tmp, path)
    except OSError as e:
        raise PlotError(f"{path}: cannot write: {e}") from None
    finally:
        plt.close(fig)
        if os.path.exists(tmp):
            os.unlink(tmp)
