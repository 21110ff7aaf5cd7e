"""Simulated people fitted to recorded live sessions: the player, its session, many runs."""
