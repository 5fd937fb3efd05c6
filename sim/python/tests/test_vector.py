"""The vector carfollow/Follow-v0: Gymnasium's vector API, the same frames as single
environments bit for bit, a scenario per sub-environment, and a plug-in's failure naming its
sub-environment."""

import gymnasium as gym
import numpy as np
import pytest
from gymnasium.vector import AutoresetMode, VectorEnv

import carfollow

# Episodes of 10 frames: an autoreset within a short test.
SHORT = {"duration_s": 0.6}


def make_vec(n, **kwargs):
    return gym.make_vec(
        "carfollow/Follow-v0", num_envs=n, vectorization_mode="vector_entry_point", **kwargs
    )


@pytest.mark.parametrize(
    "observation,action", [("camera", "drive"), ("estimate", "longitudinal")]
)
def test_follows_the_vector_api(observation, action):
    envs = make_vec(2, observation=observation, action=action, overrides=SHORT)
    assert isinstance(envs, VectorEnv) and envs.num_envs == 2
    assert envs.metadata["autoreset_mode"] == AutoresetMode.NEXT_STEP
    single = gym.make("carfollow/Follow-v0", observation=observation, action=action)
    assert envs.single_observation_space == single.observation_space
    assert envs.single_action_space == single.action_space
    single.close()
    assert envs.observation_space == gym.vector.utils.batch_space(
        envs.single_observation_space, 2
    )
    assert envs.action_space.shape == (2, *envs.single_action_space.shape)
    obs, infos = envs.reset(seed=3)
    assert obs in envs.observation_space
    assert list(infos["frame"]) == [0, 0] and infos["_frame"].all()
    ended = np.zeros(2, dtype=bool)
    for _ in range(12):
        was_ended = ended
        obs, rewards, terminated, truncated, infos = envs.step(envs.action_space.sample())
        assert obs in envs.observation_space
        assert rewards.shape == (2,) and rewards.dtype == np.float64
        assert terminated.dtype == bool and truncated.dtype == bool
        # NEXT_STEP: the step after an episode's end starts the next, with reward 0.
        assert np.all(infos["frame"][was_ended] == 0) and np.all(rewards[was_ended] == 0)
        ended = terminated | truncated
    envs.close()


def test_seeded_sub_environments_are_single_environments_bit_for_bit():
    """Sub-environment k, reset with seed s, is a single environment reset with s + k,
    through an autoreset (whose seed each draws as the single environment does)."""
    n, seed, steps = 3, 11, 14
    rng = np.random.default_rng(0)
    actions = rng.uniform(-0.3, 0.8, size=(steps, n, 2)).astype(np.float32)
    envs = make_vec(n, scenario="weave", observation="camera", overrides=SHORT)
    obs, _ = envs.reset(seed=seed)
    vec = [(obs, None)]
    for t in range(steps):
        obs, rewards, terminated, truncated, _ = envs.step(actions[t])
        vec.append((obs, (rewards, terminated, truncated)))
    envs.close()
    resets = 0
    for k in range(n):
        env = gym.make("carfollow/Follow-v0", scenario="weave", overrides=SHORT)
        obs, _ = env.reset(seed=seed + k)
        assert np.array_equal(vec[0][0][k], obs), k
        ended = False
        for t in range(steps):
            if ended:
                obs, _ = env.reset()
                reward, terminated, truncated = 0.0, False, False
                resets += 1
            else:
                obs, reward, terminated, truncated, _ = env.step(actions[t][k])
            got, (rewards, terms, truncs) = vec[t + 1]
            assert np.array_equal(got[k], obs), (k, t)
            assert (rewards[k], terms[k], truncs[k]) == (reward, terminated, truncated), (k, t)
            ended = terminated or truncated
        env.close()
    assert resets >= n, "every sub-environment went through an autoreset"


def test_a_scenario_per_sub_environment():
    envs = make_vec(
        2, scenario=["nist-grounds", "cut-in"], observation="estimate", overrides=SHORT
    )
    obs, _ = envs.reset(seed=5)
    _, _, _, _, infos = envs.step(np.zeros((2, 2), dtype=np.float32))
    for k, scenario in enumerate(["nist-grounds", "cut-in"]):
        single = gym.make(
            "carfollow/Follow-v0", scenario=scenario, observation="estimate", overrides=SHORT
        )
        first, _ = single.reset(seed=5 + k)
        assert np.array_equal(obs[k], first), scenario
        single.close()
    names = infos["truth"]["traffic"]["vehicles"][1]
    assert [v["name"] for v in names] == ["chase", "lead", "van"]
    envs.close()
    with pytest.raises(ValueError, match="scenario: 3 given for num_envs = 2"):
        make_vec(2, scenario=["nist-grounds"] * 3)
    with pytest.raises(FileNotFoundError, match="environment 1"):
        make_vec(2, scenario=["nist-grounds", "no-such-scenario.toml"])


class Steady:
    """A tracker that always sees the lead 10 m ahead."""

    def track(self, frame, t, camera):
        return carfollow.Estimate(10.0, 0.0)


class Raises(Steady):
    """Raises from its fourth frame on."""

    def track(self, frame, t, camera):
        if t > 0.25:
            raise KeyError("the tracker's own mistake")
        return super().track(frame, t, camera)


def test_a_plugins_exception_names_its_sub_environment_and_the_others_go_on():
    envs = make_vec(3, observation="estimate", tracker=[Steady(), Raises(), Steady()])
    envs.reset(seed=1)
    zero = np.zeros((3, 2), dtype=np.float32)
    with pytest.raises(KeyError) as e:
        for _ in range(5):
            _, _, _, _, before = envs.step(zero)
    assert "the tracker's own mistake" in str(e.value)
    assert "environment 1, in the tracker at frame 4" in str(e.value)
    assert e.value.env_index == 1
    # The others took the step and go on; the failed one starts a new episode.
    obs, rewards, _, _, infos = envs.step(zero)
    assert list(infos["frame"]) == [5, 0, 5] and rewards[1] == 0.0
    assert list(before["frame"]) == [3, 3, 3]
    assert obs[0][0] == pytest.approx(10.0, abs=0.5) and obs[2][0] == pytest.approx(10.0, abs=0.5)
    envs.close()
    with pytest.raises(TypeError, match="one per sub-environment"):
        make_vec(2, tracker=Steady())
    # A factory gives each its own.
    envs = make_vec(2, observation="estimate", tracker=Steady, overrides=SHORT)
    envs.reset(seed=1)
    envs.close()
