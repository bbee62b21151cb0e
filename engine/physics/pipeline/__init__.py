"""pipeline of the physics step (map in the next commit)."""
