"""Time: temporal antialiasing (taa.py) and sequences of frames under it (sequences.py)."""
