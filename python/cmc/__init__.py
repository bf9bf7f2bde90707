"""cmc: rough, adhesive contact mechanics (the Contact Mechanics Challenge).

Pure-Python submodules (``cmc.analysis``: refinement, extrapolation, error bands and the
choice of best estimates) import without the compiled core; names of the core load it
on first use.
"""
