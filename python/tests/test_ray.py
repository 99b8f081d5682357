"""The Ray example (python/examples/ray_balance.py) on a local Ray instance of two workers: the
study spread as Ray tasks gives the serial run's outcomes bit for bit, and they make physical
sense."""

import importlib.util
import os
import sys

import numpy as np
import pytest

ray = pytest.importorskip(
    "ray", reason="ray is not installed (pip install ray): the Ray example is not tested"
)

import articulated  # noqa: E402

EXAMPLE = os.path.join(os.path.dirname(__file__), "..", "examples", "ray_balance.py")

# Small: 4 tasks of 200 runs over 1.5 s (each task's batch is still one `simulate` call).
TASKS, RUNS, SEED, HORIZON = 4, 200, 7, 1.5


@pytest.fixture(scope="module")
def example():
    """The example, imported as the module `ray_balance`."""
    spec = importlib.util.spec_from_file_location("ray_balance", os.path.abspath(EXAMPLE))
    module = importlib.util.module_from_spec(spec)
    sys.modules["ray_balance"] = module
    spec.loader.exec_module(module)
    yield module
    sys.modules.pop("ray_balance", None)


@pytest.fixture(scope="module")
def local_ray():
    """A local Ray instance with two workers (two CPUs), shut down after this module's tests;
    one that another test already started is used as it is, and left running."""
    if ray.is_initialized():
        yield ray
        return
    ray.init(num_cpus=2, include_dashboard=False, log_to_driver=False, configure_logging=False)
    try:
        yield ray
    finally:
        ray.shutdown()


@pytest.fixture(scope="module")
def serial(example):
    return example.study(TASKS, RUNS, SEED, use_ray=False, horizon=HORIZON)


def test_ray_equals_serial_bitwise(example, local_ray, serial):
    spread = example.study(TASKS, RUNS, SEED, use_ray=True, horizon=HORIZON)
    assert set(spread) == set(example.FIELDS) == set(serial)
    for name in example.FIELDS:
        assert spread[name].shape == (TASKS * RUNS,), name
        assert spread[name].dtype == serial[name].dtype, name
        # Bit for bit: the bytes, so that NaN (a faulted run's final angle) compares too.
        assert spread[name].tobytes() == serial[name].tobytes(), name
    assert example.identical(spread, serial)


def test_tasks_draw_from_their_own_seeds(example, serial):
    # Task k's runs depend on (seed, k) only: a study of fewer tasks is the same study's start.
    fewer = example.study(2, RUNS, SEED, use_ray=False, horizon=HORIZON)
    assert example.identical(fewer, {k: v[: 2 * RUNS] for k, v in serial.items()})
    # And the tasks' draws differ from each other.
    first, second = serial["payload"][:RUNS], serial["payload"][RUNS : 2 * RUNS]
    assert not np.array_equal(first, second)


def test_summary_makes_physical_sense(example, serial):
    payload, impulse = serial["payload"], serial["impulse"]
    balanced, fell = serial["balanced"], serial["fell"]
    assert not (balanced & fell).any()
    # Small pushes with payloads the regulator holds are all caught; the largest are not.
    small = (impulse < 10.0) & (payload < 40.0)
    assert small.sum() > 20 and balanced[small].all()
    large = impulse > 55.0
    assert large.sum() > 20 and fell[large].mean() > 0.9
    # Falls grow with the push; past 50 kg (near the 57 kg where the regulator designed for
    # 10 kg stops holding the upright) fewer pushes are caught.
    assert fell[impulse < 20.0].mean() < fell[(impulse > 30.0) & (impulse < 45.0)].mean()
    assert balanced[payload > 50.0].mean() < balanced[(payload > 10.0) & (payload < 40.0)].mean()
    text = example.summary(serial)
    assert f"{TASKS * RUNS} runs" in text and "fraction balanced" in text


def test_chosen_cases(example):
    model = articulated.Model.load(example.MODEL_PATH)
    assert model.param_names == ["payload"] and model.params == [example.NOMINAL_PAYLOAD]
    # (payload kg, impulse N·s): a small push at the nominal payload balances; a huge push, or
    # a payload far past what the regulator holds, falls.
    cases = np.array([[10.0, 5.0], [10.0, 80.0], [150.0, 5.0]])
    out = example.outcomes(model, cases[:, 0], cases[:, 1], np.full(3, 0.3), horizon=HORIZON)
    assert out["balanced"].tolist() == [True, False, False]
    assert out["fell"].tolist() == [False, True, True]


@pytest.mark.parametrize("payload", [0.0, 10.0, 50.0])
def test_no_push_stays_upright(example, payload):
    # The upright is an equilibrium at every payload: the regulator holds it, unpushed.
    model = articulated.Model.load(example.MODEL_PATH)
    q_eq, gain, tau_eq = example.regulator(model)
    result = model.simulate(
        q_eq, np.zeros(model.nv), 2.0, example.DT, gain=gain, q_ref=q_eq, tau_ref=tau_eq,
        params=np.array([payload]), drives=True,
    )
    assert result["faults"] is None
    assert np.abs(result["q"] - q_eq).max() <= 1e-9
    assert np.abs(result["v"]).max() <= 1e-9
