"""The project's analysis of runs, written once and tested (tests/analysis/): the reports
(reports/) and the scripts that write the references (scripts/) read files, call these functions
and draw or format what they return; none of them computes a band or an extrapolation itself.

- refinement: observed order, Richardson extrapolation, the error of a refinement sequence and
  the challenge's own refinement of a Tabor-sweep point.
- bands: the change of a value or a curve under one refinement, the band of a curve or a
  cross-section profile on the finest grid of a sequence (twice the change from the next coarser
  grid), the bands of a hard-wall load sweep, and the interpolation in a quantity's representation.
- family: the scaled family's members and the error a resolution strategy has on them.
- conditions: a run's band from the family at mu_T = 3 and 250 kPa and at its own mu_T or load,
  and the check of that band at other conditions.
- transfer: whether the family's errors carry over to the challenge (the transfer check), and
  the strategies' deviations on other realizations against their targets.
- s_route: the family's values extrapolated in s to the challenge (the second route).
- best, challenge, extremum, runs: the run store, the choice of best estimates and the mean
  gap's extremum in mu_T.
- speed: the runs at the reference load as cost against error from the best estimates, and
  their Pareto front.

Why Python: the analysis reads JSON stores and CSVs and feeds matplotlib reports and the
reference writers, all Python (numpy only here). Two formulas also exist in C++: `cmc refine`
(validation/Refine.cpp, validation/Validate.cpp fit_order) makes its refinement table, the
relative change between grids and the observed order, inside the command line, which must not
need Python. refinement.py says how the two correspond; the tests feed both the same numbers.
"""
