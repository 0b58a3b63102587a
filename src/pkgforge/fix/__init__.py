"""`pkgforge fix`: apply the fixes that verify's findings describe, keeping every other byte.

edits.py reads files, applies located edits bottom-up, parses again and writes
atomically; registry.py registers one fixer per check name (the check
registry's `fix` field says which checks have one, and whether it is safe or
unsafe), written in fixers.py, rviz_fixers.py and launch_fixers.py; run.py
runs verify, the fixers and verify again.
"""
