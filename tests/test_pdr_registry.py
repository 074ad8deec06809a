"""The step-detector registry (ilocalg.pdr.registry): every detector obeys the one contract."""

import numpy as np
import pandas as pd
import pytest

import ilocalg.pdr as pdr
from ilocalg.pdr.registry import DETECTOR_RATE_HZ, STEP_CONTRACT, STEP_DETECTORS, register_step_detector
from ilocalg.pdr.signals import acc_from_log
from ilocalg.sim import gait

#: Parameters for the simulated walk at 50 Hz (SAM: ranges learned below; sign change: an MA wide
#: enough for 50 Hz, as the ILC study uses; the others: their defaults).
PARAMS = {"peak_window": {"threshold_mps2": 1.0}, "sign_change": {"n_left": 6, "n_right": 6, "smooth": True,
                                                                "gravity_half_width": 25}}


@pytest.fixture(scope="module")
def walk():
    w = gait.make_walkers(3, 11)[2]
    return gait.simulate_walk(gait.straight_route(40.0), w, 11)


@pytest.fixture(scope="module")
def sam_ranges():
    rng = np.random.default_rng(12)
    feats = gait.fixed_length_features(gait.training_walks(gait.make_walkers(3, 11), rng))   # incl. the walker
    return pdr.learn_feature_ranges(feats, 0.0, 1.0)


def test_the_five_detectors_are_registered():
    assert {"sam", "peak_window", "robust", "find_peaks", "sign_change"} <= set(STEP_DETECTORS)
    assert DETECTOR_RATE_HZ["sam"] == 50.0 and DETECTOR_RATE_HZ["robust"] == 100.0
    assert pdr.step_detector("robust") is pdr.detect_steps_robust


@pytest.mark.parametrize("name", sorted(STEP_DETECTORS))
def test_every_detector_obeys_the_contract_on_a_seeded_walk(name, walk, sam_ranges):
    acc, t = acc_from_log(walk.imu)
    params = {"ranges": sam_ranges} if name == "sam" else PARAMS.get(name, {})
    st = pdr.detect_steps(name, acc, t, **params)
    assert isinstance(st, pd.DataFrame)
    assert set(STEP_CONTRACT) <= set(st.columns)
    i = st["i_peak"].to_numpy()
    assert np.issubdtype(i.dtype, np.integer) and i.min() >= 0 and i.max() < t.size
    np.testing.assert_allclose(st["t_s"].to_numpy(), t[i], atol=0.6 / 50)   # the step time is its sample's
    assert np.all(np.diff(st["t_s"].to_numpy()) > 0)
    assert np.all(st["a_max_mps2"].to_numpy() >= st["a_min_mps2"].to_numpy())
    n_true = len(walk.steps)
    assert abs(len(st) - n_true) <= 0.35 * n_true, (name, len(st), n_true)


@pytest.mark.parametrize("name", sorted(STEP_DETECTORS))
def test_count_steps_resamples_an_irregular_log(name, walk):
    acc, t = acc_from_log(walk.imu)
    rng = np.random.default_rng(0)
    keep = np.sort(rng.choice(t.size, int(0.9 * t.size), replace=False))   # drop 10 % of the samples
    n = pdr.count_steps(name, acc[keep], t[keep])
    assert isinstance(n, int) and n >= 0


def test_unknown_and_duplicate_names_fail_clearly():
    with pytest.raises(ValueError, match="unknown step detector 'nope'"):
        pdr.detect_steps("nope", np.zeros((10, 3)), np.arange(10.0))
    with pytest.raises(ValueError, match="already registered"):
        register_step_detector("robust")(lambda acc_mps2, t_s: None)
    with pytest.raises(ValueError, match="non-empty str"):
        register_step_detector("")


def test_adding_a_detector_is_one_decorator():
    @register_step_detector("_test_every_second")
    def every_second(acc_mps2, t_s):
        t = np.asarray(t_s)
        i = np.flatnonzero(np.diff(np.floor(t)) > 0) + 1
        a = np.linalg.norm(np.asarray(acc_mps2), axis=1)
        return pd.DataFrame({"i_peak": i, "t_s": t[i], "a_max_mps2": a[i], "a_min_mps2": a[i]})

    try:
        t = np.arange(0, 5, 0.01)
        assert pdr.count_steps("_test_every_second", np.tile([0.0, 0.0, 9.8], (t.size, 1)), t) == 4
    finally:
        STEP_DETECTORS.pop("_test_every_second")
        DETECTOR_RATE_HZ.pop("_test_every_second")


def test_sign_change_on_three_axes_equals_its_vertical_input(walk):
    acc, t = acc_from_log(walk.imu)
    v = pdr.along_gravity_mps2(acc, pdr.gravity_lowpass_mps2(acc, 25))
    a = pdr.detect_steps("sign_change", acc, t, gravity_half_width=25)
    b = pdr.detect_steps("sign_change", v, t)
    pd.testing.assert_frame_equal(a, b)


def test_cli_methods_are_registered_detectors():
    from ilocalg.workflow.commands import evaluate_steps

    assert set(evaluate_steps.METHODS) <= set(STEP_DETECTORS)
