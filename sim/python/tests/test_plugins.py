"""Trackers and controllers written in Python, in the loop."""

import csv
import subprocess

import numpy as np
import pytest

import carfollow

SHORT = {"duration_s": 4.0}

# The columns of frames.csv that only the paper's tracker run by the loop fills (its
# confidences, coverage, events, fit residual and σ²); a plug-in's are empty.
BUILTIN_ONLY = {
    "confidence_x",
    "confidence_y",
    "confidence_scale",
    "coverage_h",
    "coverage_v",
    "coverage_gain",
    "tracker_event",
    "fit_residual",
}


class Wrapped:
    """The paper's tracker behind a Python object of one's own."""

    def __init__(self, scenario="nist-grounds", overrides=None):
        self.inner = carfollow.PaperTracker(scenario, overrides)
        self.started_at = None

    def reset(self, camera, start):
        assert isinstance(camera, carfollow.Camera) and camera.width == 256
        self.started_at = start
        self.inner.reset(camera, start)

    def track(self, frame, t, camera):
        assert frame.shape == (242, 256) and frame.dtype == np.uint8
        return self.inner.track(frame, t, camera)


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.mark.parametrize("mode", ["paper", "robust"])
def test_the_paper_tracker_wrapped_in_python_gives_carfollow_runs_frames(tmp_path, carfollow_bin, mode):
    overrides = {"duration_s": 6.0, "seed": 2, "tracker.mode": mode}
    native = tmp_path / "native"
    args = [str(carfollow_bin), "run", "scenarios/weave.toml", "--quiet", "--out", str(native)]
    for k, v in overrides.items():
        args += ["--set", f"{k}={v}"]
    from conftest import REPO

    # A shortened run fails its scenario's criteria (exit 1); it must complete.
    assert subprocess.run(args, cwd=REPO).returncode in (0, 1)
    tracker = Wrapped("weave", {"tracker.mode": mode})
    sim = carfollow.Simulation(
        REPO / "scenarios" / "weave.toml",
        seed=2,
        overrides={"duration_s": 6.0, "tracker.mode": mode},
        tracker=tracker,
    )
    summary = sim.run(out=tmp_path / "plugin")
    assert tracker.started_at is not None and tracker.started_at.cx is not None
    assert summary["tracker"] == "Wrapped"
    a, b = read(native / "frames.csv"), read(tmp_path / "plugin" / "frames.csv")
    assert len(a) == len(b) == 90
    for k, (ra, rb) in enumerate(zip(a, b)):
        for column, value in ra.items():
            if column in BUILTIN_ONLY or column.startswith("sigma2_"):
                assert rb[column] == "", (k, column)
            else:
                assert rb[column] == value, (k, column, value, rb[column])


class Raises:
    def __init__(self, at_frame):
        self.at = at_frame
        self.calls = 0

    def track(self, frame, t, camera):
        self.calls += 1
        if self.calls > self.at:
            raise KeyError("the tracker's own mistake")
        return carfollow.Estimate(10.0, 0.0)


def test_a_tracker_that_raises_ends_the_run_with_its_exception():
    sim = carfollow.Simulation("nist-grounds", overrides=SHORT, tracker=Raises(5))
    for _ in range(5):
        assert sim.step()
    with pytest.raises(KeyError) as e:
        sim.step()
    message = str(e.value)
    assert "the tracker's own mistake" in message
    assert "frame 5" in message and "t = 0.333 s" in message
    assert not sim.step(), "nothing runs after the failure"


class BadController:
    def control(self, inp):
        if inp.t > 0.5:
            raise ValueError("no")
        return carfollow.Command(0.0, 0.1, 0.0)


def test_a_controller_that_raises_ends_the_run_with_its_exception():
    sim = carfollow.Simulation("nist-grounds", overrides=SHORT, controller=BadController())
    with pytest.raises(ValueError, match=r"no \(carfollow: in the controller at frame 7"):
        sim.run()


def test_a_plugin_returning_the_wrong_type_is_a_type_error():
    class Wrong:
        def track(self, frame, t, camera):
            return (10.0, 0.0)

    with pytest.raises(TypeError, match="must return a carfollow.Estimate or None"):
        carfollow.Simulation("nist-grounds", overrides=SHORT, tracker=Wrong()).step()
    with pytest.raises(TypeError, match="has no method `track`"):
        carfollow.Simulation("nist-grounds", tracker=object())


class Follower:
    """A constant-time-gap controller on the delayed estimate, steering at its bearing."""

    name = "follower"

    def __init__(self):
        self.inputs = 0
        self.last = None

    def control(self, inp):
        self.inputs += 1
        e = inp.estimate
        if e is None:
            self.last = carfollow.Command(0.0, 0.0, 0.0)
            return self.last
        gap_error = e.range_m - (5.0 + 1.0 * inp.speed_mps)
        longitudinal = max(-1.0, min(1.0, 0.3 * gap_error))
        steer = 0.8 * e.lateral_m / e.range_m
        self.last = carfollow.Command(steer, max(longitudinal, 0.0), max(-longitudinal, 0.0))
        return self.last


def test_a_python_controller_drives_and_is_named():
    c = Follower()
    # One renderer: with two, the physics runs a frame ahead of the records.
    sim = carfollow.Simulation(
        "nist-grounds", seed=4, overrides={"duration_s": 10.0}, controller=c, renderers=1
    )
    while sim.step():
        # The record's controls are the last physics step's: the controller's last command
        # (as the vehicle takes it, in f32; frames.csv's steering turns positive left).
        r = sim.record
        for column, value in [
            ("throttle", c.last.throttle),
            ("brake", c.last.brake),
            ("steering_rad", -c.last.steering_rad),
        ]:
            assert abs(r[column] - value) < 1e-6, (column, r[column], value)
    assert c.inputs == 10 * 120, "called at every physics step"
    summary = sim.write_outputs(__import__("tempfile").mkdtemp())
    assert summary["controller"] == "follower" and summary["frames"] == 150


def test_estimates_and_commands_refuse_what_the_loop_cannot_use():
    with pytest.raises(ValueError, match="range_m"):
        carfollow.Estimate(float("nan"), 0.0)
    with pytest.raises(ValueError, match="status"):
        carfollow.Estimate(10.0, 0.0, status="fine")
    with pytest.raises(ValueError, match="throttle"):
        carfollow.Command(0.0, 1.5, 0.0)


class SteerRight:
    """Holds the speed and steers right: the chase must turn right."""

    def __init__(self):
        self.first = None
        self.last = None

    def control(self, inp):
        self.first = self.first or inp
        self.last = inp
        return carfollow.Command(0.1, 0.3 if inp.speed_mps < 6.0 else 0.0, 0.0)


def test_steering_and_yaw_rate_turn_positive_to_the_right():
    c = SteerRight()
    sim = carfollow.Simulation("nist-grounds", overrides={"duration_s": 3.0}, controller=c)
    while sim.step():
        pass
    assert c.last.steering_rad > 0.05, c.last
    assert c.last.yaw_rate_rad_s > 0.0, c.last
    # The heading grows towards +z, the vehicle's right.
    assert c.last.heading_rad > c.first.heading_rad + 0.1, (c.first, c.last)
    # The lead drives straight on: it is now to the left of the camera.
    assert sim.truth["lateral_m"] < -0.5, sim.truth


class Claims(Wrapped):
    """The paper's tracker on `cut-in`, saying it holds vehicle `vehicle` (an index in the
    truth's "vehicles" list, or None)."""

    def __init__(self, vehicle):
        super().__init__("cut-in")
        self.vehicle = vehicle

    def track(self, frame, t, camera):
        e = self.inner.track(frame, t, camera)
        if e is None:
            return None
        return carfollow.Estimate(
            e.range_m, e.lateral_m, e.cx, e.cy, e.scale, e.status, e.vertical_m, vehicle=self.vehicle
        )


def held_in_cut_in(vehicle, seconds=5.0):
    """Each frame's (tracked_vehicle, lost) for `Claims(vehicle)` on the first seconds of
    `cut-in`, before the van leaves its lane."""
    sim = carfollow.Simulation("cut-in", overrides={"duration_s": seconds}, tracker=Claims(vehicle))
    held = []
    while sim.step():
        truth = sim.truth
        held.append((truth["traffic"]["tracked_vehicle"], truth["lost"]))
    return sim, held


def test_a_tracker_that_says_which_vehicle_it_holds_is_judged_by_its_word():
    sim, unsaid = held_in_cut_in(None)
    names = [v["name"] for v in sim.truth["traffic"]["vehicles"]]
    assert names[:2] == ["chase", "lead"] and "van" in names
    assert unsaid and all(held == ("lead", False) for held in unsaid)
    # Saying it holds the lead, which it does: judged the same as saying nothing.
    assert held_in_cut_in(names.index("lead"))[1] == unsaid
    # Saying it holds the van while its estimate is on the lead's board: it holds nothing,
    # and the lead in its path is lost.
    said_van = held_in_cut_in(names.index("van"))[1]
    assert len(said_van) == len(unsaid)
    assert all(held == (None, True) for held in said_van)
    e = carfollow.Estimate(10.0, 0.0, vehicle=2)
    assert e.vehicle == 2 and "vehicle=2" in repr(e)
    assert carfollow.Estimate(10.0, 0.0).vehicle is None


def test_a_vehicle_the_scenario_does_not_have_ends_the_run_naming_it():
    with pytest.raises(Exception, match=r"vehicle = 9: no such target \(1 is the lead, 2 the one actor\)"):
        held_in_cut_in(9, seconds=1.0)
    with pytest.raises(Exception, match=r"vehicle = 0: no such target"):
        carfollow.Simulation("nist-grounds", overrides=SHORT, tracker=Claims(0)).step()
    with pytest.raises(OverflowError):
        carfollow.Estimate(10.0, 0.0, vehicle=-1)
