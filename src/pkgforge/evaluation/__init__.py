"""What user content a launch worker's request evaluates, above the sandbox that confines it."""
