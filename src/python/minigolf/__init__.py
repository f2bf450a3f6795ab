"""minigolf: a simulated Barrett WAM that learns to putt (thesis: Kronander, 2011).

Units everywhere: metres, seconds, radians, m/s. Errors: ValueError (bad input), OSError (files),
minigolf.NumericalError (an algorithm could not deliver), with the messages of the `minigolf` CLI.

    >>> import minigolf
    >>> system = minigolf.System(field="flat")
    >>> r = system.putt(angle=0.0, speed=1.2, ball_only=True)
    >>> r.sunk, r.trajectory.shape            # doctest: +SKIP

The Gymnasium environment is `minigolf.env.PuttEnv`; `minigolf.make("minigolf/PuttBall-v0")` (or
`gymnasium.make`, when gymnasium is installed: the ids are registered on import) builds one.
"""
from . import _paths  # noqa: F401  (before the extension: it sets the data folder)
from ._minigolf import (  # noqa: F401
    Data,
    Evaluation,
    Example,
    Field,
    HittingModel,
    ImaginedCache,
    LaneRegion,
    LaunchSkill,
    Model,
    NumericalError,
    PuttResult,
    Situations,
    System,
    SystemData,
    Renderer,
    World,
    calibrate_launch_skill,
    club_speed_range,
    courses,
    end_of_stroke,
    fast_putt,
    line_blocked,
    load_course,
    load_dataset,
    mpi_built,
    plan_stroke,
    play,
    read_plant_file,
    real_hole,
    train,
)

load_model = Model.load


def putt(angle, speed, field="flat", ball_only=False, **kwargs):
    """One putt on a fresh System of `field` (see System.putt; build a System to putt many times)."""
    return System(field=field).putt(angle, speed, ball_only=ball_only, **kwargs)


from . import env  # noqa: E402,F401
from . import round_env  # noqa: E402,F401
from .env import make, make_vec  # noqa: E402,F401

env.register_envs()
