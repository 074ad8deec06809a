"""The sweep toy with ``run_many`` (several runs computed together), for the batch path of the sweep tests."""

from tests.sweep_toy import run

#: The number of runs of each run_many call, in order.
CALLS: list[int] = []


def run_many(runs):
    CALLS.append(len(runs))
    return [run(**r) for r in runs]
