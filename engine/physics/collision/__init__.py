"""collision of the physics step (map in commit C)."""
