"""``carfollow/Follow-v0``: car following as a Gymnasium environment.

``gymnasium.make("carfollow/Follow-v0", scenario="nist-grounds", observation="camera",
action="drive", render_mode=None, overrides=None, tracker=None)``

``gymnasium.make_vec("carfollow/Follow-v0", num_envs=N, ...)`` gives N of them stepped
together in one process (``carfollow.vector.FollowVectorEnv``).

One step is one camera frame (1/15 s), with the eight 120 Hz physics steps in it. The
scenario drives the lead vehicle; the agent drives the chase vehicle.

Actions
-------
``action="drive"``: ``Box(-1, 1, (2,))``: steering (±1 is full lock, 0.41 rad, positive to the right) and the
longitudinal command (throttle above 0, brake below). ``action="longitudinal"``:
``Box(-1, 1, (1,))``: the longitudinal command only; the built-in controller steers (pure
pursuit on the paper's tracker's delayed estimates) and aims the pan head.

An action takes effect after the scenario's latency (``loop.latency_ms``, 128 ms by default,
with its jitter and drops), counted from the capture of the frame it answers, as the
built-in tracker's estimates reach the built-in controller: the agent stands where the
tracker and the controller stand together. Until the first action arrives the chase
coasts. The scenario's latency less its jitter must be at least one frame.

Observations
------------
``observation="camera"``: ``Box(0, 255, (1, 242, 256), uint8)``, the camera frame,
channel-first (as stable-baselines3 takes images). The actions still in flight are not in
it: an agent that needs them keeps its own last actions (frame stacking, a recurrent
policy), or reads ``info["actions_in_flight"]``.

``observation="estimate"``: ``Box(low, high, (12,), float32)``, the paper's tracker's
estimate as it reaches the controller, with the chase's own state:

====  ===================================  ============================
 0    range to the target, m               0 when there is none
 1    lateral offset of the target, m      positive to the right
 2    the estimate's age, s                10 when there is none
 3    its status                           1 tracking, 0.5 coasting,
                                           0 lost, −1 none yet
 4    the chase's speed, m/s
 5    its yaw rate, rad/s                  positive turning right
 6    its steering angle, rad
 7    the pan head's reading, rad          0 for a fixed camera
 8–11 the last two actions (steer, long.)  newest first; in flight
====  ===================================  ============================

Each value is clipped to its bound (``carfollow.env.ESTIMATE_LOW`` and ``ESTIMATE_HIGH``).

Reward, termination
-------------------
Each frame: +1 with the gap (camera to the target) inside the scenario's ``expect.gap_band_m``
(5–15 m without one), else minus the distance outside it over 5 m (down to −1); −1 when the
target is out of the camera's view; −10 on a collision; less 0.1 times the change of the
action since the last. ``terminated`` on a collision or when the chase leaves the road
(more than 1.5 lane widths from the lead's path); ``truncated`` at the scenario's end.

``info`` holds the simulated time ``t``, the ``frame``, the ground ``truth`` (for scoring; an
agent that acts on it cheats), the frame's ``record`` (every column of frames.csv) and the
``actions_in_flight``. It holds no wall-clock time.

``tracker``: a tracker plug-in (an object with ``track(frame, t, camera)``, as
``carfollow.Simulation`` takes) in place of the paper's: its estimates reach the built-in
steering and the estimate observation. An exception it raises is raised from ``step`` (or
``reset``) with the frame and time added.

``reset(seed=...)`` is reproducible: the same seed gives the same episode, bit for bit. The
renderer is made at the first reset, in the process that steps the environment, so that
``gymnasium.vector.AsyncVectorEnv`` workers each make their own.
"""

from __future__ import annotations

from typing import Any, Optional

import numpy as np

import gymnasium as gym
from gymnasium import spaces

from ._carfollow import GymCore, estimate_space

_low, _high = estimate_space()
ESTIMATE_LOW = np.asarray(_low, dtype=np.float32)
ESTIMATE_HIGH = np.asarray(_high, dtype=np.float32)
del _low, _high


class FollowEnv(gym.Env):
    """Car following as a Gymnasium environment (see the module's notes)."""

    metadata = {"render_modes": ["rgb_array"], "render_fps": 15}

    def __init__(
        self,
        scenario: Any = "nist-grounds",
        observation: str = "camera",
        action: str = "drive",
        render_mode: Optional[str] = None,
        overrides: Optional[dict] = None,
        tracker: Any = None,
    ) -> None:
        if observation not in ("camera", "estimate"):
            raise ValueError(f'observation = {observation!r}: must be "camera" or "estimate"')
        if action not in ("drive", "longitudinal"):
            raise ValueError(f'action = {action!r}: must be "drive" or "longitudinal"')
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f'render_mode = {render_mode!r}: must be None or "rgb_array"')
        self.render_mode = render_mode
        self._observation = observation
        self._action = action
        self._scenario = str(scenario) if not isinstance(scenario, str) else scenario
        # Whole frames only where something looks at them.
        camera = observation == "camera" or render_mode == "rgb_array"
        self._core = GymCore(
            self._scenario, overrides, action=action, camera=camera, tracker=tracker
        )
        # Bad input fails here, before any renderer exists (none is made until reset).
        self._frames = self._core.check()
        if observation == "camera":
            self.observation_space = spaces.Box(0, 255, (1, 242, 256), np.uint8)
        else:
            self.observation_space = spaces.Box(ESTIMATE_LOW, ESTIMATE_HIGH, dtype=np.float32)
        n = 2 if action == "drive" else 1
        self.action_space = spaces.Box(-1.0, 1.0, (n,), np.float32)
        self._started = False

    def _obs(self) -> np.ndarray:
        if self._observation == "camera":
            return self._core.frame()[None, :, :]
        return self._core.estimate_observation()

    def reset(
        self, *, seed: Optional[int] = None, options: Optional[dict] = None
    ) -> tuple[np.ndarray, dict]:
        """Starts an episode: with ``seed``, the scenario run with that seed; without one,
        the scenario's own seed first, then seeds drawn from the first episode's, so a run
        of episodes is reproducible. Returns the first observation and ``info``."""
        super().reset(seed=seed)
        if seed is None and self._started:
            # A new episode of its own, reproducible from the first seed.
            seed = int(self.np_random.integers(0, 2**31 - 1))
        self._core.reset(seed)
        self._started = True
        return self._obs(), self._core.info()

    def step(self, action: Any) -> tuple[np.ndarray, float, bool, bool, dict]:
        """Applies ``action`` (in [-1, 1]: steering and throttle/brake, or throttle/brake
        alone with ``action="longitudinal"``) through the scenario's latency and runs to the
        next camera frame: ``(observation, reward, terminated, truncated, info)``."""
        a = np.asarray(action, dtype=np.float64).reshape(-1)
        if self._action == "drive":
            steer, longitudinal = float(a[0]), float(a[1])
        else:
            steer, longitudinal = 0.0, float(a[0])
        reward, terminated, truncated = self._core.step(steer, longitudinal)
        return self._obs(), float(reward), bool(terminated), bool(truncated), self._core.info()

    def render(self) -> Optional[np.ndarray]:
        """With ``render_mode="rgb_array"``, the last camera frame as RGB (242, 256, 3);
        otherwise None."""
        if self.render_mode != "rgb_array":
            return None
        grey = self._core.frame()
        return np.repeat(grey[:, :, None], 3, axis=2)

    def close(self) -> None:
        """Ends the episode and frees the renderer."""
        self._core.close()
