"""Notebook-scale experiments, each returning tables (lists of dicts) for the notebooks."""
