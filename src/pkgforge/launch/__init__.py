"""Resolving launch files in an install tree, in worker subprocesses."""
