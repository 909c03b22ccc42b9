"""Hostile-input fuzzing: every entry point raises only postdsl's located errors, in time."""
