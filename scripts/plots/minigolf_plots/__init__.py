"""Plots for the minigolf experiments' report: one module per figure kind, a shared CSV reader
(common.read_csv) whose problems become one 'plot: error:' line, and the command line (cli)."""
from .common import PlotError, read_csv  # noqa: F401
from .dataset import plot_dataset  # noqa: F401
from .demo import plot_demo  # noqa: F401
from .field import plot_field  # noqa: F401
from .launch_error import plot_launch_error  # noqa: F401
from .learning_curve import plot_learning_curve  # noqa: F401
from .model import plot_model  # noqa: F401
from .success import plot_success  # noqa: F401
from .sweep import plot_sweep  # noqa: F401
