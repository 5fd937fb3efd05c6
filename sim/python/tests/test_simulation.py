"""carfollow.Simulation: stepping, outputs, bad input, and the interpreter released."""

import json
import threading
import time

import numpy as np
import pytest

import carfollow

SHORT = {"duration_s": 2.0}


def test_steps_one_frame_at_a_time_and_exposes_it():
    sim = carfollow.Simulation("nist-grounds", seed=4, overrides=SHORT)
    assert sim.frame is None and sim.t == 0.0 and not sim.done
    assert sim.step()
    frame = sim.frame
    assert frame.dtype == np.uint8 and frame.shape == (242, 256)
    assert frame.std() > 5, "a rendered frame, not a blank one"
    truth, estimate = sim.truth, sim.estimate
    assert truth["in_view"] and abs(truth["range_m"] - estimate["range_m"]) < 1.0
    assert truth["partly_out_of_view"] is False
    assert estimate["status"] in ("tracking", "coasting", "lost")
    assert sim.step() and abs(sim.t - 1 / 15) < 1e-12
    assert sim.record["frame"] == 1
    while sim.step():
        pass
    assert sim.done and sim.frame_index == 29


def test_run_writes_the_usual_outputs(tmp_path):
    sim = carfollow.Simulation("nist-grounds", seed=4, overrides=SHORT)
    sim.step()
    summary = sim.run(out=tmp_path)
    for name in ["frames.csv", "summary.json", "junit.xml", "gap.png"]:
        assert (tmp_path / name).is_file(), name
    on_disk = json.loads((tmp_path / "summary.json").read_text())
    assert on_disk["frames"] == summary["frames"] == 30
    assert on_disk["tracker"] == "paper tracker (paper mode)"
    assert on_disk["controller"] == "pure pursuit and gap keeper"
    rows = (tmp_path / "frames.csv").read_text().splitlines()
    assert len(rows) == 31, "header and every frame, the one stepped before run() included"
    with pytest.raises(RuntimeError, match="finished"):
        sim.step()


def test_write_outputs_after_stepping(tmp_path):
    sim = carfollow.Simulation("weave", seed=2, overrides=SHORT)
    for _ in range(10):
        sim.step()
    summary = sim.write_outputs(tmp_path)
    assert summary["frames"] == 10
    assert len((tmp_path / "frames.csv").read_text().splitlines()) == 11


def test_the_same_seed_gives_the_same_run():
    def run():
        sim = carfollow.Simulation("swerves", seed=3, overrides=SHORT)
        frames = []
        while sim.step():
            frames.append((sim.frame.copy(), sim.record))
        return frames

    a, b = run(), run()
    assert len(a) == len(b) == 30
    for (fa, ra), (fb, rb) in zip(a, b):
        assert np.array_equal(fa, fb)
        assert ra == rb


def test_bad_input_raises_value_error_with_checks_line(tmp_path):
    with pytest.raises(ValueError, match=r"--set tracker.lambda=1.5: `tracker.lambda` = 1.5"):
        carfollow.Simulation("nist-grounds", overrides={"tracker.lambda": 1.5})
    bad = tmp_path / "bad.toml"
    text = (carfollow_scenarios() / "nist-grounds.toml").read_text()
    bad.write_text(text.replace("duration_s = 90.0", "duraton_s = 90.0"))
    with pytest.raises(ValueError) as e:
        carfollow.Simulation(bad)
    message = str(e.value)
    assert message.startswith(f"{bad}:") and "duraton_s" in message and "\n" not in message
    with pytest.raises(ValueError, match="unknown field"):
        carfollow.check(bad)
    with pytest.raises(ValueError, match="must be a bool, int, float, str"):
        carfollow.Simulation("nist-grounds", overrides={"duration_s": object()})
    assert list(tmp_path.iterdir()) == [bad], "nothing written on a refused input"


def test_a_missing_file_raises_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError):
        carfollow.Simulation(tmp_path / "nowhere.toml")
    with pytest.raises(FileNotFoundError):
        carfollow.Simulation("no-such-scenario")


def test_scenario_text_runs():
    text = (carfollow_scenarios() / "nist-grounds.toml").read_text()
    sim = carfollow.Simulation(text, overrides={"duration_s": 1.0})
    assert sim.name == "nist-grounds" and sim.step()


def test_the_interpreter_is_released_while_the_loop_runs():
    sim = carfollow.Simulation("nist-grounds", seed=4, overrides={"duration_s": 6.0}, renderers=1)
    ticks = []
    stop = threading.Event()

    def count():
        while not stop.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=count)
    t.start()
    started = time.perf_counter()
    sim.run()
    ended = time.perf_counter()
    stop.set()
    t.join()
    during = [x for x in ticks if started < x < ended]
    # Held throughout, the other thread would not tick at all while run() ran.
    assert len(during) > 10, f"{len(during)} ticks in {ended - started:.2f} s"


def carfollow_scenarios():
    from conftest import SCENARIOS

    return SCENARIOS


def test_the_truth_lists_every_vehicle_of_a_traffic_scenario():
    sim = carfollow.Simulation("cut-in", overrides={"duration_s": 12.0})
    assert sim.step()
    traffic = sim.truth["traffic"]
    names = [v["name"] for v in traffic["vehicles"]]
    assert names == ["chase", "lead", "van"]
    van = traffic["vehicles"][2]
    assert van["kind"] == "van" and abs(van["speed_mps"] - 9.7) < 0.5
    assert traffic["path_vehicle"] == "lead" and traffic["tracked_vehicle"] == "lead"
    events = []
    while sim.step():
        events += sim.truth["traffic"]["events"]
    assert events == ["van/cut-in:started"]
    # Without traffic the truth has no such entry.
    plain = carfollow.Simulation("nist-grounds", overrides=SHORT)
    plain.step()
    assert "traffic" not in plain.truth


def test_an_openscenario_file_runs_as_any_scenario():
    from conftest import REPO

    path = REPO / "sim" / "core" / "tests" / "data" / "openscenario" / "cut-in.xosc"
    sim = carfollow.Simulation(str(path), overrides={"duration_s": 2.0})
    frames = 0
    while sim.step():
        frames += 1
    assert frames == 30
    names = [v["name"] for v in sim.truth["traffic"]["vehicles"]]
    assert names == ["chase", "lead", "Cutter"]
    bad = REPO / "sim" / "core" / "tests" / "data" / "openscenario" / "catalogs" / "VehicleCatalog.xosc"
    with pytest.raises(ValueError, match="a catalog or a parameter distribution, not a scenario"):
        carfollow.Simulation(str(bad))


def end_run_scenario(at_s: float) -> str:
    """The library's cut-in with an event that ends the run at `at_s`."""
    text = (carfollow_scenarios() / "cut-in.toml").read_text()
    return text + (
        '\n[[actors.events]]\nname = "end"\n'
        f"trigger = {{ time_s = {at_s} }}\naction = {{ end_run = true }}\n"
    )


def test_an_event_that_ends_the_run_ends_it_here_too():
    sim = carfollow.Simulation(end_run_scenario(2.0))
    frames = 0
    while sim.step():
        frames += 1
    # The end starts at the physics step of 2.0 s, in frame 30's physics: its last frame.
    assert frames == 31 and sim.done
    summary = sim.run()
    assert summary["ended_by"] == {"vehicle": "van", "event": "end", "t_s": 2.0}
    assert summary["frames"] == 31
