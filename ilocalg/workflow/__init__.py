"""Workflow code: the reproduce runner, report writing, seed and parameter sweeps, notebook pairs, the CLI.

Nothing here computes a position. The algorithm packages (``ilocalg.wifi``, ``ilocalg.pdr``, ...) and the
experiment modules never import this package (the study_* sweeps use its task plumbing in ``studies``); it
imports them.
"""
