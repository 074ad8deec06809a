"""Measurements of the simulators' world parameters from public recordings.

The same functions run on real recordings (``../shared/data``) and on simulator output, so a
simulated world can be checked against the recordings it was built from (notebook
16_measured_worlds). :mod:`ilocalg.measure.table` builds ``data/measured_parameters.csv`` from the
shared data; :mod:`ilocalg.sim.measured` reads it for the simulators.

Data types
----------
Wi-Fi scans
    A long DataFrame with one row per (scan, AP): columns ``t_s`` (scan timestamp, s), ``scan_id``,
    ``bssid``, ``rssi_dbm`` and, for readings that carry it, ``last_seen_s`` (when the AP was last
    heard, s, same clock as ``t_s``); the format of :attr:`ilocalg.io.ilc.IlcTrace.wifi`.
Statistic with its interval
    :class:`ilocalg.measure.stats.Estimate`: value, 95 % bootstrap interval (percentile method,
    seeded), n, unit. Resampling is by cluster (walk, AP or recording) whenever the values are
    grouped, because values within a walk are not independent.

Modules
-------
stats    bootstrap intervals
scans    scan interval and reading age (lag) of Wi-Fi scans while walking
radio    path-loss fit, shadowing, device offset, drift, detection probability, APs per scan
gait     step-to-step variability, amplitude spread, gait correlations
heading  phone heading vs walking direction, magnetic disturbance
sources  iterators over the shared recordings (ILC site1 archive, UJIIndoorLoc, Oxford)
table    the measured-parameter table: build, write
simulated  the same statistics measured on simulator output, side by side with the real ones
"""

from ilocalg.measure.stats import Estimate, bootstrap

__all__ = ["Estimate", "bootstrap"]
