"""Tests of the SQPnP reference (OpenCV)."""

import numpy as np
import pytest

from ilocalg.photo import look_at, pnp_solve, pnp_solve_batch, project

F = 1045.0
POIS = np.array([[-1.2, 0, 1.6], [-0.8, 0, 2.1], [-0.4, 0, 1.62], [0, 0, 1.58], [0.4, 0, 1.61], [0.8, 0, 1.59],
                 [1.2, 0, 1.1]])


@pytest.mark.parametrize("idx", [[0, 1, 5, 6], list(range(7))])
def test_exact_recovery_noise_free(idx):
    c = np.array([0.3, 4.5, 1.42])
    T = look_at(c, POIS.mean(axis=0), 0.04)
    U = project(POIS, c, T, F)
    res = pnp_solve(POIS[idx], U[idx], F)
    np.testing.assert_allclose(res.c_m, c, atol=1e-6)
    np.testing.assert_allclose(res.T, T, atol=1e-7)
    np.testing.assert_allclose(pnp_solve_batch(POIS[idx], U[idx][None], F)[0], c, atol=1e-6)


def test_bad_input_raises():
    c = np.array([0.3, 4.5, 1.42])
    U = project(POIS, c, look_at(c, POIS.mean(axis=0)), F)
    with pytest.raises(ValueError, match="at least 4"):
        pnp_solve(POIS[:3], U[:3], F)
    line = np.array([[-1.0, 0, 1.5], [0, 0, 1.5], [1.0, 0, 1.5], [2.0, 0, 1.5]])
    with pytest.raises(ValueError, match="collinear"):
        pnp_solve(line, U[:4], F)


def test_importing_ilocalg_photo_does_not_load_cv2_or_matplotlib():
    import os
    import subprocess
    import sys
    from pathlib import Path

    root = str(Path(__file__).resolve().parents[1])
    env = {**os.environ, "PYTHONPATH": root + os.pathsep + os.environ.get("PYTHONPATH", "")}

    code = "import sys, ilocalg.photo, ilocalg.experiments.photo_positioning; " \
           "print('cv2' in sys.modules, 'matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env=env, cwd=root).stdout.split()
    assert out == ["False", "False"]
