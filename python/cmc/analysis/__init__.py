"""The project's analysis of runs, written once and tested: grid refinement and
Richardson extrapolation, error bands, and the choice of best estimates."""
