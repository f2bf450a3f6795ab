"""Plots for the minigolf experiments' report: one module per figure kind, a shared CSV reader
(common.read_csv) whose problems become one 'plot: error:' line, and the command line (cli)."""
from .common import PlotError, read_csv
from .dataset import plot_dataset
from .demo import plot_demo
from .ds import plot_ds
from .field import plot_field
from .launch_error import plot_launch_error
from .learning_curve import plot_learning_curve
from .model import plot_model
from .round import plot_round
from .strength import plot_strength
from .success import plot_success
from .sweep import plot_sweep

__all__ = ["PlotError", "read_csv", "plot_dataset", "plot_demo", "plot_field", "plot_launch_error",
           "plot_learning_curve", "plot_model", "plot_round", "plot_success", "plot_sweep", "plot_ds",
           "plot_strength"]
