"""A tiny experiment for the sweep tests: the mean of ``n`` normal draws, with an optional failure."""

import numpy as np
import pandas as pd

from ilocalg.papers import comparison_table, paper_ref


def run(seed=0, fast=False, n=50, scale=1.0, fail_seed=None):
    if seed == fail_seed:
        raise RuntimeError(f"toy failure at seed {seed}")
    x = np.random.default_rng(seed).normal(0.0, scale, n // 2 if fast else n)
    comp = comparison_table([paper_ref("Toy paper", "Table 1", "mean of normals", 0.05, x.mean(), "-")])
    study = pd.DataFrame({"quantity": ["std of normals"], "value": [x.std()]})
    return {"comparison": comp, "sweep_std": study, "ignored": pd.DataFrame({"a": [1]})}
