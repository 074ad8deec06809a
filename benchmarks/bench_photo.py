"""Speed of the batched photo solvers against per-photo reference loops (pytest-benchmark).

Run: ``PYTHONPATH=$PWD python -m pytest benchmarks/bench_photo.py --benchmark-only``. The ratio to the
reference, measured in the same run, is stored in ``extra_info``; nothing here asserts a time.
"""

import numpy as np
import pytest
from conftest import best_time_s
from scipy.optimize import least_squares

from ilocalg.photo import measured_view_angles_rad, st_solve_batch, st_system, va_solve_batch, view_angles_rad
from ilocalg.sim import photo_poi

pytest.importorskip("pytest_benchmark")


@pytest.fixture(scope="module")
def photos():
    return photo_poi.simulate(0, n_photos=30)


def test_bench_st_batch_vs_lstsq_loop(benchmark, photos):
    s = photos

    def ref():
        for b in range(s.c_m.shape[0]):
            A, y = st_system(s.pois_m, s.img_px[b], s.f_px, s.T_meas[b])
            np.linalg.lstsq(A, y, rcond=None)

    t_ref = best_time_s(ref, repeat=3)
    benchmark(st_solve_batch, s.pois_m, s.img_px, s.f_px, s.T_meas)
    ours = best_time_s(lambda: st_solve_batch(s.pois_m, s.img_px, s.f_px, s.T_meas))
    benchmark.extra_info["speedup_vs_lstsq_loop"] = t_ref / ours


def test_bench_va_batch_vs_scipy_loop(benchmark, photos):
    s = photos
    a = measured_view_angles_rad(s.img_px, s.f_px)

    def ref():
        for b in range(s.c_m.shape[0]):
            least_squares(lambda x, b=b: view_angles_rad(x[None], s.pois_m[None])[0] - a[b], s.c0_good_m[b])

    t_ref = best_time_s(ref, repeat=1)
    benchmark.pedantic(va_solve_batch, args=(s.pois_m, a, s.c0_good_m), rounds=3, iterations=1)
    ours = best_time_s(lambda: va_solve_batch(s.pois_m, a, s.c0_good_m), repeat=1)
    benchmark.extra_info["speedup_vs_scipy_least_squares_loop"] = t_ref / ours
