"""A live participant in the loop: the session engine, its inputs, picking and pacing."""
