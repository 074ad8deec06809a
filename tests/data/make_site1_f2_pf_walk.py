"""Write ``site1_f2_pf_walk.json``: the particle filter's inputs on one site1 F2 walk (issue 26).

The walk 5dda5a8b9191710006b573da scored leave-one-walk-out with the nested Wi-Fi selection, exactly as
``fusion_real_walks.run(seed=0, dataset="ilc2020_site1/site1_F2", names=[WALK])`` scores it: the PDR
headings and step lengths, the Wi-Fi fixes on the states and their covariances, the start, and the
filter's keywords (without ``recovery``; the errors stored are those of the filter without it, as
issue 26 reported them), as :func:`ilocalg.track.evaluate_walk` passes them to
:func:`ilocalg.fusion.particle_filter.map_particle_filter` (captured at that call, so nothing here
repeats the pipeline). Derived numbers only (no recording is copied); the ground truth is read from
../shared/data by the test. Run from the repository root::

    PYTHONPATH=$PWD python tests/data/make_site1_f2_pf_walk.py
"""

import json
from pathlib import Path

import numpy as np

import ilocalg.track.evaluation as ev
from ilocalg.experiments import fusion_real_walks as frw

WALK = "5dda5a8b9191710006b573da"
DATASET = "ilc2020_site1/site1_F2"
OUT = Path(__file__).with_name("site1_f2_pf_walk.json")


def main():
    seen = {}
    orig = ev.map_particle_filter

    def capture(*args, **kw):
        seen["args"], seen["kw"] = args, kw
        return orig(*args, **kw)

    orig_walk = frw.evaluate_walk

    def capture_walk(*args, **kw):
        out = orig_walk(*args, **kw)
        seen["state_t_s"] = out["state_t_s"]
        return out

    ev.map_particle_filter, frw.evaluate_walk = capture, capture_walk
    try:
        res = frw.run(seed=0, dataset=DATASET, names=[WALK], methods=("wifi", "pf"),
                      cfg=frw.RealWalkConfig(pf_recovery=None))
    finally:
        ev.map_particle_filter, frw.evaluate_walk = orig, orig_walk
    x0, P0, th, d, z, R = (np.asarray(a, dtype=float) for a in seen["args"])
    kw = {k: v for k, v in seen["kw"].items() if k not in ("grid", "rng", "recovery")}
    g = seen["kw"]["grid"]
    pw = res["per_walk"].iloc[0]
    out = {"walk": WALK, "dataset": DATASET, "made_by": "tests/data/make_site1_f2_pf_walk.py",
           "wifi_config": pw["wifi_config"], "fix_sd_m": float(pw["fix_sd_m"]), "grid_cell_m": g.cell_m,
           "state_t_s": np.asarray(seen["state_t_s"], dtype=float).tolist(),
           "x0_m": x0.tolist(), "P0_m2": P0.tolist(), "theta_rad": th.tolist(), "step_m": d.tolist(),
           "z_m": [None if np.isnan(r[0]) else r.tolist() for r in z], "R_m2": R.tolist(), "pf_kw": kw,
           "rng_seed": [0, frw.load_floor(None, DATASET).names.index(WALK)],
           "errors_m": {m: float(pw[m]) for m in ("wifi", "pf")}}
    OUT.write_text(json.dumps(out, indent=None, separators=(",", ":")) + "\n")
    print(f"wrote {OUT} ({OUT.stat().st_size} bytes)")


if __name__ == "__main__":
    main()
