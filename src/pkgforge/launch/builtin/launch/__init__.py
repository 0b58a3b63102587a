"""The built-in engine's `launch`: contexts, substitutions, conditions, actions, events, sources."""
