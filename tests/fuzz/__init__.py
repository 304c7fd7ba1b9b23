"""Fuzzing ``usdksl check``: mutated sample files and random scenes, each run with a time budget."""
