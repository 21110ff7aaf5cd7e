"""A physical episode: its run, step log, video recorder, render checks, and sweep runs."""
