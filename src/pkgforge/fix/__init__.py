"""`pkgforge fix`: apply the fixes that verify's findings describe, keeping every other byte.

edits.py reads files, applies located edits bottom-up, parses again and writes
atomically; fixers.py holds one fixer per check name (the registry's `fix`
field says which checks have one, and whether it is safe or unsafe); run.py
runs verify, the fixers and verify again.
"""
