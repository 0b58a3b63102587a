"""`pkgforge verify` (and `colcon verify`): the pipeline, its cache, configuration, explain output and progress."""
