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
        """The chase's heading by its odometry, radians, from the world's +x towards +z."""

class Camera:
    """The camera a tracker is given: intrinsics, image size, mount, the pan head's reading
    at the frame's capture, and the target model. Read-only."""

    @property
    def focal_length_mm(self) -> float: ...
    @property
    def pixel_size_mm(self) -> tuple[float, float]: ...
    @property
    def focal_px(self) -> tuple[float, float]: ...
    @property
    def image_center_px(self) -> tuple[float, float]: ...
    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def mount_height_m(self) -> float: ...
    @property
    def mount_forward_m(self) -> float: ...
    @property
    def mount_pitch_down_deg(self) -> float: ...
    @property
    def pan_rad(self) -> float: ...
    @property
    def gyro_rad(self) -> Optional[tuple[float, float, float]]:
        """The camera's rotation since the previous frame (rotation vector, radians), with
        the gyro's bias and noise; None without a gyro, on the first frame and in reset()."""
    @property
    def target_size_m(self) -> tuple[float, float]: ...
    @property
    def target_nominal_range_m(self) -> float: ...
    @property
    def target_size_px(self) -> tuple[float, float]: ...
    @property
    def target_segments(self) -> list[tuple[tuple[float, float], tuple[float, float]]]: ...
    def project(self, x: float, y: float, z: float) -> Optional[tuple[float, float]]:
        """A point in the camera frame (metres, x right, y down, z forward) in image pixels;
        None behind the camera."""

class Tracker(Protocol):
    """What ``Simulation(tracker=...)`` takes (``reset`` is optional)."""

    def track(
        self, frame: npt.NDArray[np.uint8], t: float, camera: Camera
    ) -> Optional[Estimate]: ...

class Controller(Protocol):
    """What ``Simulation(controller=...)`` takes."""

    def control(self, inp: ControlInput) -> Command: ...

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
        """Runs one camera frame; False when the scenario was over already."""
    @property
    def done(self) -> bool: ...
    @property
    def t(self) -> float: ...
    @property
    def frame_index(self) -> Optional[int]: ...
    @property
    def frame(self) -> Optional[npt.NDArray[np.uint8]]:
        """The last camera frame, shape (242, 256); None before the first step."""
    @property
    def truth(self) -> Optional[dict[str, Any]]: ...
    @property
    def estimate(self) -> Optional[dict[str, Any]]: ...
    @property
    def estimate_object(self) -> Optional[Estimate]: ...
    @property
    def record(self) -> Optional[dict[str, Any]]:
        """The last frame's record: every column of frames.csv."""
    @property
    def name(self) -> str: ...
    @property
    def frames(self) -> int: ...
    @property
    def tracker_name(self) -> str: ...
    @property
    def controller_name(self) -> str: ...
    def run(self, out: Optional[Union[str, os.PathLike[str]]] = None) -> dict[str, Any]:
        """Runs to the end; writes the usual outputs into ``out`` when given; returns the
        summary (as summary.json has it)."""
    def write_outputs(self, dir: Union[str, os.PathLike[str]]) -> dict[str, Any]:
        """Writes the outputs of the frames run so far and returns the summary."""

class PaperTracker:
    """The paper's tracker with a scenario's ``[tracker]`` settings, as a Python tracker."""

    def __init__(
        self, scenario: Optional[Scenario] = None, overrides: Optional[Overrides] = None
    ) -> None: ...
    @property
    def name(self) -> str: ...
    def reset(self, camera: Camera, start: Optional[Estimate] = None) -> None: ...
    def track(
        self, frame: npt.NDArray[np.uint8], t: float, camera: Camera
    ) -> Optional[Estimate]: ...

class GymCore:
    """The native core of ``carfollow.env.FollowEnv`` (use the environment instead)."""

    def __init__(
        self,
        scenario: Scenario,
        overrides: Optional[Overrides] = None,
        action: Literal["drive", "longitudinal"] = "drive",
        camera: bool = True,
        backend: Optional[str] = None,
    ) -> None: ...
    def check(self) -> int: ...
    def reset(self, seed: Optional[int] = None) -> None: ...
    def step(self, steer: float, longitudinal: float) -> tuple[float, bool, bool]: ...
    def frame(self) -> npt.NDArray[np.uint8]: ...
    def estimate_observation(self) -> npt.NDArray[np.float32]: ...
    def info(self) -> dict[str, Any]: ...
    def frames(self) -> int: ...
    def close(self) -> None: ...

def shipped_scenarios() -> list[str]:
    """The names of the shipped scenarios."""

def check(
    scenario: Scenario, seed: Optional[int] = None, overrides: Optional[Overrides] = None
) -> str:
    """Checks a scenario as ``carfollow check`` does; returns its name or raises
    ValueError (FileNotFoundError for a missing file)."""

def estimate_space() -> tuple[list[float], list[float]]:
    """The estimate observation's bounds (low, high)."""
