"""The run stores: the challenge runs (reference/challenge/runs.json, runs) and the seed
ensemble's (reference/challenge/ensemble/runs.json, ensemble), each a command's work."""
