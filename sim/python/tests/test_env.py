"""carfollow/Follow-v0 under Gymnasium's own checks, seeded, and vectorised."""

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import carfollow  # noqa: F401  (registers carfollow/Follow-v0)


@pytest.mark.parametrize("observation", ["camera", "estimate"])
@pytest.mark.parametrize("action", ["drive", "longitudinal"])
def test_passes_check_env(observation, action):
    env = gym.make(
        "carfollow/Follow-v0",
        scenario="nist-grounds",
        observation=observation,
        action=action,
        overrides={"duration_s": 5.0},
    )
    check_env(env.unwrapped, skip_render_check=True)
    env.close()


def test_the_same_seed_gives_the_same_observations_for_300_steps():
    def episode():
        env = gym.make("carfollow/Follow-v0", scenario="weave", observation="camera")
        obs, _ = env.reset(seed=7)
        seen = [obs]
        rng = np.random.default_rng(0)
        for _ in range(300):
            action = rng.uniform(-0.2, 0.6, size=2).astype(np.float32)
            obs, reward, terminated, truncated, info = env.step(action)
            seen.append((obs, reward, info["truth"]["gap_m"]))
            if terminated or truncated:
                # The next episode's seed comes from the first: reproducible too.
                obs, _ = env.reset()
                seen.append((obs, 0.0, 0.0))
        env.close()
        return seen

    a, b = episode(), episode()
    assert len(a) == len(b) >= 301
    assert np.array_equal(a[0], b[0])
    for (oa, ra, ga), (ob, rb, gb) in zip(a[1:], b[1:]):
        assert np.array_equal(oa, ob) and ra == rb and ga == gb


def test_an_action_takes_effect_after_the_latency():
    # 300 ms is 36 physics steps: the action on frame 0 applies from step 36, in the physics
    # from frame 4 to 5 (steps 32–39), which frame 4's record shows.
    env = gym.make(
        "carfollow/Follow-v0",
        scenario="nist-grounds",
        observation="estimate",
        overrides={"loop.latency_ms": 300.0},
    )
    _, info = env.reset(seed=1)
    throttle = [info["record"]["throttle"]]
    for _ in range(5):
        _, _, _, _, info = env.step(np.array([0.0, 1.0], dtype=np.float32))
        throttle.append(info["record"]["throttle"])
    env.close()
    assert throttle == [0.0, 0.0, 0.0, 0.0, 1.0, 1.0]


def test_info_holds_no_wall_clock_time():
    env = gym.make("carfollow/Follow-v0", scenario="nist-grounds", observation="estimate")
    _, info = env.reset(seed=1)
    keys = set(info) | set(info["record"])
    assert not any("wall" in k or "realtime" in k or "timing" in k for k in keys)
    env.close()


def test_bad_arguments_are_value_errors():
    with pytest.raises(ValueError, match="observation"):
        gym.make("carfollow/Follow-v0", observation="lidar")
    with pytest.raises(ValueError, match="latency"):
        gym.make("carfollow/Follow-v0", overrides={"loop.latency_ms": 20.0})


def test_a_scenario_without_a_lead_is_refused_by_the_follow_task():
    # Its reward is the gap kept to the lead: a scenario without one has no such gap.
    with pytest.raises(RuntimeError, match="has no lead"):
        env = gym.make(
            "carfollow/Follow-v0", scenario="stopped-car-ahead", observation="estimate"
        )
        env.reset(seed=1)


def make_env(seed_offset):
    def make():
        return gym.make(
            "carfollow/Follow-v0",
            scenario="nist-grounds",
            observation="estimate",
            overrides={"duration_s": 3.0},
        )

    return make


def test_async_vector_env_with_two_workers():
    envs = gym.vector.AsyncVectorEnv([make_env(0), make_env(1)])
    obs, _ = envs.reset(seed=[1, 2])
    assert obs.shape == (2, 12)
    for _ in range(20):
        obs, rewards, terminated, truncated, infos = envs.step(
            np.tile(np.array([0.0, 0.3], dtype=np.float32), (2, 1))
        )
    assert obs.shape == (2, 12) and np.all(np.isfinite(obs))
    envs.close()
    # Each worker is reproducible on its own: worker 0 again with seed 1.
    single = make_env(0)()
    first, _ = single.reset(seed=1)
    again = gym.vector.AsyncVectorEnv([make_env(0)])
    o, _ = again.reset(seed=[1])
    assert np.array_equal(o[0], first)
    again.close()
    single.close()


def test_follow_runs_a_traffic_scenario_and_reports_its_truth():
    env = gym.make("carfollow/Follow-v0", scenario="cut-in", observation="estimate")
    env.reset(seed=4)
    for _ in range(20):
        _, _, terminated, truncated, info = env.step(env.action_space.sample() * 0.0)
        assert not (terminated or truncated)
    assert [v["name"] for v in info["truth"]["traffic"]["vehicles"]] == ["chase", "lead", "van"]
    env.close()


def test_an_event_that_ends_the_run_truncates_the_episode(tmp_path):
    from conftest import SCENARIOS

    path = tmp_path / "end.toml"
    text = (SCENARIOS / "cut-in.toml").read_text().replace(
        'target = "targets/', f'target = "{SCENARIOS}/targets/'
    )
    path.write_text(
        text + '\n[[actors.events]]\nname = "end"\ntrigger = { time_s = 2.0 }\n'
        "action = { end_run = true }\n"
    )
    env = gym.make("carfollow/Follow-v0", scenario=str(path), observation="estimate")
    env.reset(seed=4)
    # The run's last frame is frame 30 (the end starts in its physics): the 30th step.
    for k in range(1, 31):
        _, _, terminated, truncated, _ = env.step(env.action_space.sample() * 0.0)
        assert not terminated
        assert truncated == (k == 30), k
    env.close()
