"""``carfollow/Follow-v0`` as a vector environment: N simulations stepped together in one
process.

``gymnasium.make_vec("carfollow/Follow-v0", num_envs=8,
vectorization_mode="vector_entry_point", scenario="nist-grounds", observation="camera",
action="drive")``

Each sub-environment is the single environment (``carfollow.env.FollowEnv``: the same
actions, observations, reward and ``info``), run by the same native code; the N of them step
at once, each on a thread of its own with the interpreter released, and each renders its
next camera frame in the background as soon as its step returns. Mesa's llvmpipe renders
one EGL display's frames one at a time, so the odd-numbered sub-environments render on its
software EGL device and the even-numbered on wgpu's display: two frames at once. Reset with ``seed=s``,
sub-environment k gives the frames a single environment reset with ``seed=s + k`` gives, bit
for bit.

Arguments
---------
``scenario``, ``overrides``: as the single environment's, or a list of ``num_envs`` of
them, one per sub-environment (a different scenario in each). ``observation``, ``action``,
``render_mode``: as the single environment's, the same for all. ``tracker``: a tracker
plug-in for each sub-environment in place of the paper's (its estimates reach the estimate
observation): a list of ``num_envs`` objects, or a factory (a class, a function without
arguments) called once per sub-environment.

Autoreset
---------
Gymnasium's ``NEXT_STEP`` mode (``metadata["autoreset_mode"]``): the step after the one on
which a sub-environment's episode ended resets it, ignoring its action, and returns the new
episode's first observation, reward 0, neither terminated nor truncated. Each
sub-environment draws the seeds of its later episodes as the single environment does, from
the seed it was last reset with. ``reset(options={"reset_mask": mask})`` resets only the
sub-environments where ``mask`` is true.

Errors
------
An exception of one sub-environment (its tracker plug-in, a scenario that cannot be
planned, an error of its loop, a Rust panic) is raised after every sub-environment has run
its step, with "environment k" in its message and ``env_index`` = k on it; that
sub-environment's episode ends there and the next ``step`` resets it (as an episode that
ended). The others have taken the step and go on from there.
"""

from __future__ import annotations

from typing import Any, Callable, Optional, Sequence, Union

import numpy as np

import gymnasium as gym
from gymnasium import spaces
from gymnasium.utils import seeding
from gymnasium.vector.utils import batch_space

from ._carfollow import VecCore
from .env import ESTIMATE_HIGH, ESTIMATE_LOW

try:  # Gymnasium 1.1 and later name the modes.
    from gymnasium.vector import AutoresetMode

    _NEXT_STEP: Any = AutoresetMode.NEXT_STEP
except ImportError:  # pragma: no cover - Gymnasium 1.0 has NEXT_STEP only
    _NEXT_STEP = "NextStep"

# The largest seed a sub-environment draws for its next episode (as FollowEnv does).
_SEED_BOUND = 2**31 - 1


def _per_env(value: Any, n: int, what: str) -> list:
    """``value`` for each of ``n`` sub-environments: a list of ``n`` as it is, else ``n``
    times the one value."""
    if isinstance(value, (list, tuple)):
        if len(value) != n:
            raise ValueError(f"{what}: {len(value)} given for num_envs = {n}")
        return list(value)
    return [value] * n


def _trackers(tracker: Any, n: int) -> Optional[list]:
    """One tracker per sub-environment: a list of ``n``, or a factory called ``n`` times."""
    if tracker is None:
        return None
    if isinstance(tracker, (list, tuple)):
        return _per_env(tracker, n, "tracker")
    if isinstance(tracker, type) or (callable(tracker) and not hasattr(tracker, "track")):
        return [tracker() for _ in range(n)]
    raise TypeError(
        "tracker: one per sub-environment is needed (they keep state): a list of num_envs "
        "trackers, or a factory (a class, a function without arguments)"
    )


class FollowVectorEnv(gym.vector.VectorEnv):
    """``num_envs`` car-following environments stepped together (see the module's notes)."""

    metadata = {
        "render_modes": ["rgb_array"],
        "render_fps": 15,
        "autoreset_mode": _NEXT_STEP,
    }

    def __init__(
        self,
        num_envs: int = 1,
        scenario: Union[Any, Sequence[Any]] = "nist-grounds",
        observation: str = "camera",
        action: str = "drive",
        render_mode: Optional[str] = None,
        overrides: Union[None, dict, Sequence[Optional[dict]]] = None,
        tracker: Union[None, Sequence[Any], Callable[[], Any]] = None,
    ) -> None:
        if int(num_envs) < 1:
            raise ValueError(f"num_envs = {num_envs}: must be at least 1")
        if observation not in ("camera", "estimate"):
            raise ValueError(f'observation = {observation!r}: must be "camera" or "estimate"')
        if action not in ("drive", "longitudinal"):
            raise ValueError(f'action = {action!r}: must be "drive" or "longitudinal"')
        if render_mode not in (None, "rgb_array"):
            raise ValueError(f'render_mode = {render_mode!r}: must be None or "rgb_array"')
        n = int(num_envs)
        self.num_envs = n
        self.render_mode = render_mode
        self._observation = observation
        self._action = action
        scenarios = [
            s if isinstance(s, (str, dict)) else str(s)
            for s in _per_env(scenario, n, "scenario")
        ]
        camera = observation == "camera" or render_mode == "rgb_array"
        self._core = VecCore(
            scenarios,
            _per_env(overrides, n, "overrides"),
            _trackers(tracker, n),
            action=action,
            camera=camera,
        )
        # Bad input fails here, before any renderer exists (none is made until reset).
        self._frames = self._core.check()
        if observation == "camera":
            self.single_observation_space = spaces.Box(0, 255, (1, 242, 256), np.uint8)
        else:
            self.single_observation_space = spaces.Box(
                ESTIMATE_LOW, ESTIMATE_HIGH, dtype=np.float32
            )
        k = 2 if action == "drive" else 1
        self.single_action_space = spaces.Box(-1.0, 1.0, (k,), np.float32)
        self.observation_space = batch_space(self.single_observation_space, n)
        self.action_space = batch_space(self.single_action_space, n)
        # Each sub-environment's generator of its next episode's seed (None until seeded).
        self._rngs: list[Optional[np.random.Generator]] = [None] * n
        self._started = np.zeros(n, dtype=bool)
        # Sub-environments whose episode ended: the next step resets them.
        self._autoreset = np.zeros(n, dtype=bool)

    def _rng(self, k: int) -> np.random.Generator:
        if self._rngs[k] is None:
            self._rngs[k], _ = seeding.np_random()
        return self._rngs[k]

    def _seed_for(self, k: int, seed: Optional[int]) -> Optional[int]:
        """The seed sub-environment k's next episode runs with, as FollowEnv chooses it."""
        if seed is not None:
            self._rngs[k], _ = seeding.np_random(int(seed))
            return int(seed)
        if not self._started[k]:
            return None  # the scenario's own seed
        return int(self._rng(k).integers(0, _SEED_BOUND))

    def _obs(self) -> np.ndarray:
        if self._observation == "camera":
            return self._core.frames()
        return self._core.estimate_observations()

    def _infos(self) -> dict:
        infos: dict = {}
        for k, info in enumerate(self._core.infos()):
            infos = self._add_info(infos, info, k)
        return infos

    def reset(
        self,
        *,
        seed: Union[None, int, Sequence[Optional[int]]] = None,
        options: Optional[dict] = None,
    ) -> tuple[np.ndarray, dict]:
        """Starts an episode in every sub-environment (those of ``options["reset_mask"]``
        alone, when given): with ``seed`` an int, sub-environment k runs with ``seed + k``;
        a list gives each its own. Returns the observations and ``info``."""
        n = self.num_envs
        if seed is None or isinstance(seed, (int, np.integer)):
            seeds = [None if seed is None else int(seed) + k for k in range(n)]
        else:
            seeds = _per_env(list(seed), n, "seed")
        mask = np.ones(n, dtype=bool)
        if options and "reset_mask" in options:
            mask = np.asarray(options["reset_mask"], dtype=bool).reshape(n)
        resets = [(k, self._seed_for(k, seeds[k])) for k in range(n) if mask[k]]
        self._core.reset_some(resets)
        self._started[mask] = True
        self._autoreset[mask] = False
        return self._obs(), self._infos()

    def step(
        self, actions: Any
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, dict]:
        """Steps every sub-environment with its row of ``actions`` (shape
        ``(num_envs, 2)``, or ``(num_envs, 1)`` with ``action="longitudinal"``); those whose
        episode ended on the last step are reset instead."""
        n = self.num_envs
        a = np.asarray(actions, dtype=np.float64).reshape(n, -1)
        if self._action == "drive":
            rows = np.ascontiguousarray(a[:, :2])
        else:
            rows = np.zeros((n, 2))
            rows[:, 1] = a[:, 0]
        resets = [(k, self._seed_for(k, None)) for k in np.flatnonzero(self._autoreset)]
        try:
            rewards, terminated, truncated = self._core.step(rows, resets)
        except Exception:
            # The failed sub-environments start again at the next step; the others go on.
            self._autoreset[:] = False
            self._autoreset[self._core.missing()] = True
            raise
        self._autoreset = terminated | truncated
        return self._obs(), rewards, terminated, truncated, self._infos()

    def render(self) -> Optional[tuple]:
        """With ``render_mode="rgb_array"``, each sub-environment's last camera frame as
        RGB (242, 256, 3); otherwise None."""
        if self.render_mode != "rgb_array":
            return None
        grey = self._core.frames()[:, 0]
        return tuple(np.repeat(g[:, :, None], 3, axis=2) for g in grey)

    def close_extras(self, **kwargs: Any) -> None:
        """Ends every episode and frees the renderers."""
        self._core.close()
