"""carfollow: a closed-loop car-following simulator around the model-based vision tracker of
Schneiderman, Nashman and Lumia (NIST), "Model-based vision for car following".

- ``Simulation(scenario, seed=None, overrides=None, tracker=None, controller=None)``: a
  scenario's run, stepped one camera frame (1/15 s) at a time, with the usual outputs.
- A tracker of your own is any object with ``track(frame, t, camera) -> Estimate | None``
  (and optionally ``reset(camera, start)``); a controller any object with
  ``control(input: ControlInput) -> Command``.
- ``gymnasium.make("carfollow/Follow-v0", ...)``: the Gymnasium environment, registered
  when this package is imported (with gymnasium installed); ``gymnasium.make_vec(
  "carfollow/Follow-v0", num_envs=N, ...)``: N of them stepped together in one process.

Frames are numpy ``uint8`` arrays of shape (242, 256), row-major, origin at the top-left
corner, pixel centres at integer coordinates.
"""

import os as _os

# Mesa's llvmpipe rasterises on a pool of threads unless told not to; a process forked
# after the pool exists (gymnasium's AsyncVectorEnv workers, multiprocessing's default on
# Linux) inherits its locks without its threads and hangs at its first frame. Each renderer
# rasterising on its own thread is as fast here (the loop keeps two renderers busy) and
# leaves nothing to inherit. Set LP_NUM_THREADS before importing carfollow to choose.
_os.environ.setdefault("LP_NUM_THREADS", "0")

from ._carfollow import (  # noqa: E402
    Camera,
    Command,
    ControlInput,
    Estimate,
    PaperTracker,
    Simulation,
    __version__,
    check,
    shipped_scenarios,
)

__all__ = [
    "Camera",
    "Command",
    "ControlInput",
    "Estimate",
    "PaperTracker",
    "Simulation",
    "__version__",
    "check",
    "shipped_scenarios",
]


def _register() -> None:
    try:
        from gymnasium.envs.registration import register, registry
    except ImportError:  # gymnasium is optional: pip install carfollow[gym]
        return
    if "carfollow/Follow-v0" not in registry:
        register(
            id="carfollow/Follow-v0",
            entry_point="carfollow.env:FollowEnv",
            vector_entry_point="carfollow.vector:FollowVectorEnv",
        )


_register()
