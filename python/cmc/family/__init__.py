"""The scaled challenge family (scripts/scaled_family.py): its runs (runs), its store and README
(store) and the command over them (command). What the runs measure is computed in
cmc.analysis (family, conditions, transfer, s_route)."""
