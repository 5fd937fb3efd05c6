"""Type stubs of carfollow's native module (``carfollow._carfollow``)."""

from __future__ import annotations

import os
from typing import Any, Literal, Mapping, Optional, Protocol, Union

import numpy as np
import numpy.typing as npt

__version__: str

Status = Literal["tracking", "coasting", "lost"]
Scenario = Union[str, os.PathLike[str]]
Overrides = Mapping[str, Any]

class Estimate:
    """A tracker's estimate of the target in the camera's frame (x right, y down, z forward,
    metres), with its image location where the tracker has one."""

    def __init__(
        self,
        range_m: float,
        lateral_m: float,
        cx: Optional[float] = None,
        cy: Optional[float] = None,
        scale: Optional[float] = None,
        status: Status = "tracking",
        vertical_m: Optional[float] = None,
        vehicle: Optional[int] = None,
    ) -> None: ...
    @property
    def range_m(self) -> float:
        """Distance ahead along the optical axis, metres."""
    @property
    def lateral_m(self) -> float:
        """Offset to the right, metres."""
    @property
    def vertical_m(self) -> Optional[float]:
        """Offset downwards, metres (None: from cy, else 0)."""
    @property
    def cx(self) -> Optional[float]:
        """The target's centre in the image, pixels (x)."""
    @property
    def cy(self) -> Optional[float]:
        """The target's centre in the image, pixels (y)."""
    @property
    def scale(self) -> Optional[float]:
        """The target's size relative to its size at the nominal range."""
    @property
    def status(self) -> Status:
        """"tracking", "coasting" or "lost"."""
    @property
    def vehicle(self) -> Optional[int]:
        """The vehicle the tracker says it holds: its index in the truth's "vehicles" list
        (1 the lead, 2 on the actors; without a lead, 1 on), or None when it does not say."""
    def __eq__(self, other: object) -> bool: ...

class Command:
    """A controller's commands for one physics step."""

    def __init__(
        self, steering_rad: float, throttle: float, brake: float, pan_rate_rad_s: float = 0.0
    ) -> None: ...
    @property
    def steering_rad(self) -> float:
        """Road-wheel steering angle asked for, radians, positive to the right."""
    @property
    def throttle(self) -> float:
        """Throttle, 0–1."""
    @property
    def brake(self) -> float:
        """Brake, 0–1."""
    @property
    def pan_rate_rad_s(self) -> float:
        """The pan head's rate asked for, rad/s."""
    def __eq__(self, other: object) -> bool: ...

class ControlInput:
    """What a controller is given at one physics step: the delayed estimate and the chase's
    own state. Read-only."""

    @property
    def estimate(self) -> Optional[Estimate]:
        """The latest estimate the delay line has delivered (None before the first)."""
    @property
    def fresh(self) -> bool:
        """Whether ``estimate`` arrived at this step."""
    @property
    def captured_t(self) -> Optional[float]:
        """The capture time of the estimate's frame, seconds."""
    @property
    def captured_pan_rad(self) -> Optional[float]:
        """The pan head's reading at the estimate's capture, radians."""
    @property
    def t(self) -> float:
        """The time now, seconds."""
    @property
    def speed_mps(self) -> float:
        """The chase's forward speed, m/s."""
    @property
    def yaw_rate_rad_s(self) -> float:
        """The chase's yaw rate, rad/s (positive turning right)."""
    @property
    def steering_rad(self) -> float:
        """The chase's steering angle now, radians (positive to the right)."""
    @property
    def pan_rad(self) -> float:
        """The pan head's encoder reading, radians (0 for a fixed camera)."""
    @property
    def position_m(self) -> tuple[float, float, float]:
        """The chase's rear axle in the world by its odometry, metres (x, y up, z)."""
    @property
    def heading_rad(self) -> float:
        """The chase's heading by its odometry, radians: the angle of its forward axis from
        the world's +x towards +z (turning right)."""

class Camera:
    """The camera a tracker is given: intrinsics, image size, mount, the pan head's reading
    at the frame's capture, and the target model. Read-only."""

    @property
    def focal_length_mm(self) -> float:
        """Focal length, millimetres."""
    @property
    def pixel_size_mm(self) -> tuple[float, float]:
        """Pixel size on the sensor, millimetres (width, height)."""
    @property
    def focal_px(self) -> tuple[float, float]:
        """The focal length in pixels (x, y)."""
    @property
    def image_center_px(self) -> tuple[float, float]:
        """The principal point, pixels (pixel centres at integer coordinates)."""
    @property
    def width(self) -> int:
        """Image width, pixels."""
    @property
    def height(self) -> int:
        """Image height, pixels."""
    @property
    def mount_height_m(self) -> float:
        """The camera's height above the ground, metres."""
    @property
    def mount_forward_m(self) -> float:
        """How far ahead of the chase's rear axle the camera sits, metres."""
    @property
    def mount_pitch_down_deg(self) -> float:
        """How far the camera is pitched down, degrees."""
    @property
    def pan_rad(self) -> float:
        """The pan head's encoder reading at the frame's capture, radians (0: fixed
        camera)."""
    @property
    def gyro_rad(self) -> Optional[tuple[float, float, float]]:
        """The chase's rate gyro: the camera's rotation since the previous frame, radians,
        as a rotation vector in the previous camera frame (+y turns the camera right, +x
        tilts it up), with the gyro's bias and noise; None on the first frame and in
        reset()."""
    @property
    def target_size_m(self) -> tuple[float, float]:
        """The target's size, metres (width, height)."""
    @property
    def target_nominal_range_m(self) -> float:
        """The range at which the target's scale is 1, metres."""
    @property
    def target_size_px(self) -> tuple[float, float]:
        """The target's size in the image at scale 1, pixels (width, height)."""
    @property
    def target_segments(self) -> list[tuple[tuple[float, float], tuple[float, float]]]:
        """The target model's line segments, metres about its centre at the nominal range (x
        right, y up): ((x0, y0), (x1, y1)) each."""
    def project(self, x: float, y: float, z: float) -> Optional[tuple[float, float]]:
        """Projects a point in the camera frame (metres, x right, y down, z forward) to
        image pixels; None behind the camera."""

class Tracker(Protocol):
    """What ``Simulation(tracker=...)`` takes (``reset`` is optional)."""

    def track(
        self, frame: npt.NDArray[np.uint8], t: float, camera: Camera
    ) -> Optional[Estimate]:
        """Tracks one frame (uint8, shape (height, width)) captured at ``t`` seconds by
        ``camera``: the estimate, or None for none this frame. An exception ends the run and
        reaches the caller."""

class Controller(Protocol):
    """What ``Simulation(controller=...)`` takes."""

    def control(self, inp: ControlInput) -> Command:
        """The commands for one physics step (120 Hz). An exception ends the run and reaches
        the caller."""

class Simulation:
    """A scenario's run, stepped one camera frame at a time.

    ``scenario`` is a path to a scenario file, the name of a shipped scenario, or scenario
    text; ``seed`` and ``overrides`` (``{"tracker.lambda": 0.7}``) change it as
    ``carfollow run --set`` does. Bad input raises ValueError (FileNotFoundError for a
    missing file)."""

    def __init__(
        self,
        scenario: Scenario,
        seed: Optional[int] = None,
        overrides: Optional[Overrides] = None,
        tracker: Optional[Tracker] = None,
        controller: Optional[Controller] = None,
        renderers: Optional[int] = None,
        whole_frames: bool = True,
        backend: Optional[str] = None,
    ) -> None: ...
    def step(self) -> bool:
        """Runs one camera frame (1/15 s, with the physics steps in it). Returns False when
        the scenario was over already."""
    @property
    def done(self) -> bool:
        """Whether the run is over."""
    @property
    def t(self) -> float:
        """The time of the last frame run, seconds (0 before the first)."""
    @property
    def frame_index(self) -> Optional[int]:
        """The index of the last frame run (None before the first)."""
    @property
    def frame(self) -> Optional[npt.NDArray[np.uint8]]:
        """The last camera frame: numpy uint8, shape (242, 256), row-major; None before the
        first step."""
    @property
    def truth(self) -> Optional[dict[str, Any]]:
        """The ground truth of the last frame (a dict; the plug-ins never see it). In a
        scenario with traffic, its "traffic" entry lists every vehicle ("vehicles": the
        chase, the lead and the actors, each with its name, kind, position, heading, speed
        and place on the road), the vehicle in the chase's path with the gap and the time to
        collision, the vehicle tracked, and the events and contacts since the last frame.
        """
    @property
    def estimate(self) -> Optional[dict[str, Any]]:
        """The tracker's estimate of the last frame (a dict; None when it had none)."""
    @property
    def estimate_object(self) -> Optional[Estimate]:
        """The last frame's estimate as a carfollow.Estimate (None when it had none)."""
    @property
    def record(self) -> Optional[dict[str, Any]]:
        """The last frame's record: every column of frames.csv (a dict)."""
    @property
    def name(self) -> str:
        """The scenario's name."""
    @property
    def frames(self) -> int:
        """How many frames the run has."""
    @property
    def tracker_name(self) -> str:
        """The tracker's name."""
    @property
    def controller_name(self) -> str:
        """The controller's name."""
    def run(self, out: Optional[Union[str, os.PathLike[str]]] = None) -> dict[str, Any]:
        """Runs to the end and returns the summary (as summary.json has it). With ``out``,
        the usual outputs are written there as the run goes: frames.csv (with the frames run
        so far), summary.json, the plots and junit.xml. The simulation is finished after
        it."""
    def write_outputs(self, dir: Union[str, os.PathLike[str]]) -> dict[str, Any]:
        """Writes the usual outputs of the frames run so far into ``dir`` (frames.csv,
        summary.json, the plots, junit.xml) and returns the summary."""

class PaperTracker:
    """The paper's tracker with a scenario's ``[tracker]`` settings, as a Python tracker."""

    def __init__(
        self, scenario: Optional[Scenario] = None, overrides: Optional[Overrides] = None
    ) -> None: ...
    @property
    def name(self) -> str:
        """Its name in reports."""
    def reset(self, camera: Camera, start: Optional[Estimate] = None) -> None:
        """Starts it on ``camera`` at ``start`` (the teleoperator's placement; it needs cx,
        cy and scale). None: robust mode searches the image; the paper's mode cannot."""
    def track(
        self, frame: npt.NDArray[np.uint8], t: float, camera: Camera
    ) -> Optional[Estimate]:
        """Stages 1–8 on one frame (uint8, height × width): the estimate."""

class GymCore:
    """The native core of ``carfollow.env.FollowEnv`` (use the environment instead)."""

    def __init__(
        self,
        scenario: Scenario,
        overrides: Optional[Overrides] = None,
        action: Literal["drive", "longitudinal"] = "drive",
        camera: bool = True,
        backend: Optional[str] = None,
        tracker: Optional[Tracker] = None,
    ) -> None: ...
    def check(self) -> int:
        """Checks the scenario (as ``carfollow check`` does) and that its latency lets an
        action be applied after the frame it answers: returns the number of frames of an
        episode."""
    def reset(self, seed: Optional[int] = None) -> None:
        """Starts an episode with the scenario's ``seed`` (its own when None), ending the
        last one first: a reset that fails leaves no episode, and ``step()`` asks for a
        reset."""
    def step(self, steer: float, longitudinal: float) -> tuple[float, bool, bool]:
        """Takes an action on the last observation and runs to the next frame. Returns
        ``(reward, terminated, truncated)``."""
    def frame(self) -> npt.NDArray[np.uint8]:
        """The last frame, uint8 (242, 256)."""
    def estimate_observation(self) -> npt.NDArray[np.float32]:
        """The estimate observation (see ``carfollow.env.FollowEnv``), float32."""
    def info(self) -> dict[str, Any]:
        """What the step's ``info`` holds: the time, the frame, the truth (for scoring; the
        agent should not act on it), the tracker's estimate, the actions in flight."""
    def frames(self) -> int:
        """The number of frames of an episode."""
    def close(self) -> None:
        """Ends the episode (frees the renderer)."""

class VecCore:
    """N episodes stepped together."""

    def __init__(
        self,
        scenarios: list[Union[Scenario, Mapping[str, Any]]],
        overrides: list[Optional[Overrides]],
        trackers: Optional[list[Optional[Tracker]]] = None,
        action: Literal["drive", "longitudinal"] = "drive",
        camera: bool = True,
        backend: Optional[str] = None,
    ) -> None: ...
    @property
    def num_envs(self) -> int:
        """The number of sub-environments."""
    def check(self) -> list[int]:
        """Checks every sub-environment's scenario (see `GymCore.check`): the frames of an
        episode of each."""
    def reset_some(self, resets: list[tuple[int, Optional[int]]]) -> None:
        """Starts a new episode in the sub-environments of `resets` (index, seed: the
        scenario's own when None), all at once; the others keep theirs as they are."""
    def step(
        self, actions: npt.NDArray[np.float64], resets: list[tuple[int, Optional[int]]]
    ) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_], npt.NDArray[np.bool_]]:
        """Steps every sub-environment with its row of `actions` (N × 2: steering, then the
        longitudinal), except those in `resets` (index, seed), which start a new episode
        instead (reward 0, neither terminated nor truncated). Returns the rewards,
        `terminated` and `truncated`, one each per sub-environment. An error of one
        sub-environment is raised naming it after all have run; its episode is gone (see
        `missing`), the others' have taken their step."""
    def missing(self) -> list[int]:
        """The sub-environments without an episode: never reset, or failed."""
    def frames(self) -> npt.NDArray[np.uint8]:
        """The last frames, uint8 (N, 1, 242, 256)."""
    def estimate_observations(self) -> npt.NDArray[np.float32]:
        """The estimate observations, float32 (N, 12)."""
    def infos(self) -> list[dict[str, Any]]:
        """Each sub-environment's `info` (see `GymCore.info`)."""
    def frames_per_episode(self) -> list[int]:
        """The number of frames of each sub-environment's episode."""
    def close(self) -> None:
        """Ends every episode (frees the renderers)."""

def shipped_scenarios() -> list[str]:
    """The names of the shipped scenarios, which ``Simulation`` takes by name."""

def check(
    scenario: Scenario, seed: Optional[int] = None, overrides: Optional[Overrides] = None
) -> str:
    """Checks a scenario as ``carfollow check`` does (parsed, validated, planned): returns
    its name, or raises ValueError with the line ``carfollow check`` prints
    (FileNotFoundError for a missing file)."""

def estimate_space() -> tuple[list[float], list[float]]:
    """The estimate observation space's bounds, for Python: (low, high) as lists."""
