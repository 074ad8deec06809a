"""Each reproduced experiment as a function.

Every module here exposes ``run(seed: int = 0, fast: bool = False, **params) -> dict[str, DataFrame]``:
simulate or load, estimate, score and return the result tables (with the paper's reference values
as labelled columns). Notebooks call it, show the tables and draw the figures; tests and sweeps
call the same function.
"""
