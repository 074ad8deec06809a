"""Workflow code: the reproduce runner, report writing, seed and parameter sweeps, notebook pairs, the CLI.

Nothing here computes a position. The algorithm packages (``ilocalg.wifi``, ``ilocalg.pdr``, ...) and the
experiments (``ilocalg.experiments``) never import this package; it imports them.
"""
