# The hard-case suite: every case in cases/hard/ is one ctest test, labelled 'hard', that runs
# `cmc validate` on it: its stability checks (validation/Stability.hpp) must pass, or fail where
# the case says cmc does not handle it yet (expected_failure). Results land in build/hard/<case>/.
# Small grids: `ctest -L hard -j2` with CMC_THREADS=1 takes minutes (docs/validation.md).
file(GLOB CMC_HARD_CASES CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/cases/hard/*.toml)
foreach(case_file ${CMC_HARD_CASES})
  get_filename_component(case_name ${case_file} NAME_WE)
  add_test(NAME hard.${case_name} COMMAND cmc validate ${case_file} --quiet --out ${CMAKE_BINARY_DIR}/hard)
  set_tests_properties(hard.${case_name} PROPERTIES LABELS hard TIMEOUT 600)
endforeach()

# A stability check can fail: the same solver stopped by a budget it cannot meet must exit 5,
# with a clear status and no NaN. (1) The low-load case with solver.max_iterations = 3: the
# solver stops, not converged, and the iterations check and the convergence line fail (the
# finite check passes: summary.json says so). (2) A budget of 2 iterations on a case whose
# solver converges in more (tests/data/hard-budget.toml): the iterations check alone fails.
set(CMC_HARD_FAIL ${CMAKE_BINARY_DIR}/hard-can-fail)
add_test(NAME hard.can_fail_solver_stopped
         COMMAND sh -c "rm -rf ${CMC_HARD_FAIL}/stopped; $<TARGET_FILE:cmc> validate ${CMAKE_SOURCE_DIR}/cases/hard/low-load.toml --quiet --set solver.max_iterations=3 --out ${CMC_HARD_FAIL}/stopped; test $? -eq 5 && /usr/bin/python3 -c \"import json; s = json.load(open('${CMC_HARD_FAIL}/stopped/hard-low-load/summary.json')); v = {c['quantity']: c for c in s['validation']}; assert s['status'] == 'not_converged', s['status']; assert v['iterations']['verdict'] == 'FAIL' and v['convergence']['verdict'] == 'FAIL'; assert v['finite']['verdict'] == 'pass', v['finite']\"")
add_test(NAME hard.can_fail_budget
         COMMAND sh -c "rm -rf ${CMC_HARD_FAIL}/budget; $<TARGET_FILE:cmc> validate ${CMAKE_SOURCE_DIR}/tests/data/hard-budget.toml --quiet --out ${CMC_HARD_FAIL}/budget; test $? -eq 5 && /usr/bin/python3 -c \"import json; s = json.load(open('${CMC_HARD_FAIL}/budget/hard-budget/summary.json')); v = {c['quantity']: c for c in s['validation']}; assert s['status'] == 'converged'; assert v['iterations']['verdict'] == 'FAIL' and v['iterations']['error'] > 2; assert 'convergence' not in v\"")
set_tests_properties(hard.can_fail_solver_stopped hard.can_fail_budget PROPERTIES LABELS "hard;quick" TIMEOUT 120)
