"""Checks: one module per area; importing a module registers its checks."""
