"""Sweeps: every configuration of a box (census), the run, its store, and its report."""
