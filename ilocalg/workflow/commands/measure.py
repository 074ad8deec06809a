"""``python -m ilocalg measure``: rewrite data/measured_parameters.csv from the shared public data."""

from __future__ import annotations

from pathlib import Path

#: ILC site1 subsample of the committed table (about 25 of 198 walks; all walks take ~8x longer)
DEFAULT_EVERY = 8

HELP = "measure the simulators' world parameters from ../shared/data and write data/measured_parameters.csv"


def add_arguments(p) -> None:
    p.add_argument("--data", default=None, help="data directory (default: ILOC_DATA_DIR or ../shared/data)")
    p.add_argument("--out", default=None, help="output CSV (default: data/measured_parameters.csv)")
    p.add_argument("--every", type=int, default=DEFAULT_EVERY,
                   help="use about 1/EVERY of the ILC site1 walks (deterministic subsample: trace id %% EVERY == 0; "
                        f"default {DEFAULT_EVERY}, the committed table's setting; 1: all 198 walks)")
    p.add_argument("--parts", default=None, help="comma list of scans,radio,gait,heading (default: all)")
    p.add_argument("--calibrate", action="store_true",
                   help="instead: solve the inverse calibration of the simulators against the committed measured "
                        "table and write data/calibrated_parameters.csv (no shared data needed; a few minutes)")


def run(args) -> Path:
    from ilocalg.measure import table as mt

    if getattr(args, "calibrate", False):
        from ilocalg.measure import calibrate

        df = calibrate.calibrate()
        out = calibrate.write_table(df, args.out or calibrate.CALIBRATED_PATH)
        print(df.to_string(index=False))
        return out

    parts = mt.PARTS if not args.parts else tuple(s.strip() for s in args.parts.split(",") if s.strip())
    df = mt.build_table(args.data, every=args.every, parts=parts)
    out = mt.write_table(df, args.out or mt.TABLE_PATH)
    print(df.to_string(index=False))
    return out
