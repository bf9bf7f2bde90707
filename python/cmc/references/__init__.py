"""The challenge reference curves (reference/challenge/): built from cmc's runs (challenge, curves,
provenance, readme) and given the best estimates (apply)."""
