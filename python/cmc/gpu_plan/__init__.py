"""The GPU reference plan (docs/user-guide/gpu.md): the runs behind the challenge's best estimates
made on a GPU machine lent for minutes, and their archive brought back here.

There, with the checkout's python/ on PYTHONPATH and nothing but Python's standard library
(scripts/gpu/full_plan.sh): plan (scripts/gpu/reference_plan.py: which stages fit the deadline,
estimated from the run store and scaled by iteration_scale) and cmc.ensemble_runner. Here:
archive (the archive read as untrusted input), store (scripts/gpu/store.py: runs into the run
store) and ingest (scripts/gpu/ingest.py: the archive into the store, the best estimates and the
references, all or nothing)."""
