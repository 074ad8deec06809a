"""Simulators that make the toolkit's embedded default data, deterministically from a seed.

One module per data set; each documents every model parameter and where its value comes from
(the data set's README under ``data/`` says the same for users). Import the module you need,
e.g. ``from ilocalg.sim import iloc_floor``.
"""
